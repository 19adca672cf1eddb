// surface.csv: the cost of the snow's surface (engine/surface) per frame, against particles and against the
// reconstruction's resolution, next to the cost of the simulation's step on the same particles. The thesis's bunny
// (assets/scenes/bunny_thesis.json) at 8 particles per cell, grown for more particles, with the surface's defaults
// (resolution 2, smoothing 3); and the smallest of those bunnies at resolutions 1 to 4. Each configuration is
// stepped (timeSteps: warm-up steps, then repeated runs), then its surface is rebuilt from the state the steps
// left: once untimed (the programs JIT-compile), then `repeats` times, each glFinish to glFinish, then `repeats`
// times more with each pass timed (PassTimer) for the split between the field and the mesh; every column is a
// median over its runs. The summary gives
// the surface's share of a frame: a frame at 30 Hz takes ⌈(1/30 s) / dt⌉ steps.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "Error.h"
#include "Experiments.h"
#include "surface/SurfaceReconstruction.h"

namespace firn::bench {

namespace {

using Clock = std::chrono::steady_clock;

struct SurfaceSetup {
  std::string series;  // "particles" or "resolution"
  BunnySetup bunny;
  double resolution = 2;
};

// The phases of one reconstruction, from the surface's pass timer (wall time, dispatch to glFinish).
struct PhaseMs {
  std::vector<double> bounds, splat, mesh;
};

void timePhases(surface::SurfaceReconstruction& surface, const Simulation& simulation, PhaseMs& phases) {
  surface.setPassTiming(true);  // starts from zero
  surface.reconstruct(simulation);
  const auto sum = [&](const std::vector<std::string>& passes) {
    double totalMs = 0;
    for (const PassTimer::PassTime& time : surface.passTimes()) {
      for (const std::string& pass : passes) {
        if (time.pass == "surface/" + pass + ".comp") totalMs += time.totalWallMs;
      }
    }
    return totalMs;
  };
  phases.bounds.push_back(sum({"measure_bounds"}));
  phases.splat.push_back(sum({"splat_density"}));
  phases.mesh.push_back(sum({"classify_cells", "scan_reduce", "scan_distribute", "emit_mesh"}));
  surface.setPassTiming(false);
}

}  // namespace

void measureSurface(BenchRun& run) {
  CsvTable table({"series", "particles", "resolution", "smoothing", "grid_nodes", "grid_mib", "vertices", "triangles",
                  "repeats", "surface_ms", "surface_ms_min", "surface_ms_max", "bounds_ms", "splat_ms", "mesh_ms",
                  "ms_per_step", "steps_per_frame", "surface_share_of_frame", "status", "renderer"});
  const Sizes& sizes = run.sizes();
  const BunnyScenes& bunnies = run.bunnies();
  constexpr double kParticlesPerCell = 8;
  constexpr double kFrameRateHz = 30;
  std::vector<SurfaceSetup> setups;
  const auto bunnyOf = [&](double particles) {
    BunnySetup bunny;
    bunny.gridCells = sizes.particleGridCells;
    bunny.scale = bunnies.scaleFor(particles, kParticlesPerCell);
    bunny.particlesPerCell = kParticlesPerCell;
    return bunny;
  };
  for (const double particles : sizes.surfaceParticles) setups.push_back({"particles", bunnyOf(particles), 2});
  for (const double resolution : sizes.surfaceResolutions) {
    setups.push_back({"resolution", bunnyOf(sizes.surfaceParticles.front()), resolution});
  }

  const int repeats = sizes.timing.repeats;
  std::string summary;
  for (const SurfaceSetup& setup : setups) {
    const std::string label = "surface, " + setup.series + ", bunny scale " + fixed(setup.bunny.scale, 3) +
                              ", resolution " + fixed(setup.resolution, 0);
    CsvTable::Row& row = table.addRow();
    row.setText("series", setup.series).set("resolution", setup.resolution).setText("renderer", run.renderer());
    try {
      Scene scene = bunnies.scene(setup.bunny);
      scene.surface.resolution = setup.resolution;
      row.set("smoothing", scene.surface.smoothing);
      const std::vector<ParticleSeed> seeds = sampleBodies(scene);
      row.setCount("particles", std::int64_t(seeds.size()));
      Simulation simulation(scene, seeds, run.gl());
      surface::SurfaceReconstruction surface(scene, seeds, run.gl());
      run.progress(label + ": " + grouped(seeds.size()) + " particles: stepping");
      const StepTiming step = timeSteps(simulation, sizes.timing);

      surface.reconstruct(simulation);
      glFinish();
      std::vector<double> wallMs;
      for (int repeat = 0; repeat < repeats; ++repeat) {
        const auto start = Clock::now();
        surface.reconstruct(simulation);
        glFinish();
        wallMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
      }
      PhaseMs phases;
      for (int repeat = 0; repeat < repeats; ++repeat) timePhases(surface, simulation, phases);

      const surface::SurfaceStats& stats = surface.stats();
      const double surfaceMs = median(wallMs);
      const double stepsPerFrame = std::ceil(1 / kFrameRateHz / scene.time.dtS - 1e-9);
      const double share = surfaceMs / (surfaceMs + stepsPerFrame * step.medianMs);
      row.setCount("grid_nodes", std::int64_t(stats.gridNodes.x) * stats.gridNodes.y * stats.gridNodes.z)
          .set("grid_mib", double(stats.gridBytes) / (1024.0 * 1024.0))
          .setCount("vertices", std::int64_t(stats.vertices))
          .setCount("triangles", std::int64_t(stats.triangles))
          .setCount("repeats", repeats)
          .set("surface_ms", surfaceMs)
          .set("surface_ms_min", *std::min_element(wallMs.begin(), wallMs.end()))
          .set("surface_ms_max", *std::max_element(wallMs.begin(), wallMs.end()))
          .set("bounds_ms", median(phases.bounds))
          .set("splat_ms", median(phases.splat))
          .set("mesh_ms", median(phases.mesh))
          .set("ms_per_step", step.medianMs)
          .set("steps_per_frame", stepsPerFrame)
          .set("surface_share_of_frame", share)
          .setText("status", "ok");
      run.progress(label + ": surface " + fixed(surfaceMs, 1) + " ms (" + grouped(stats.triangles) +
                   " triangles), a step " + fixed(step.medianMs, 1) + " ms");
      if (setup.series == "particles") {
        summary += (summary.empty() ? "" : "; ") + grouped(seeds.size()) + " particles " + fixed(surfaceMs, 1) +
                   " ms = " + fixed(surfaceMs / step.medianMs, 2) + " steps, " + fixed(100 * share, 1) + "% of a frame";
      }
    } catch (const InputError& error) {
      row.setText("status", "skipped");
      run.progress(label + ": skipped: " + error.what());
    } catch (const SimulationError& error) {
      row.setText("status", "unstable");
      run.progress(label + ": unstable: " + error.what());
    }
  }
  run.write(table, "surface");
  if (!summary.empty()) {
    run.addSummary("surface (resolution 2, smoothing 3), the thesis bunny at 8 per cell, per frame: " + summary);
  }
}

}  // namespace firn::bench
