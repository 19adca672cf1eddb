// surface.csv: the cost of the snow's surface (engine/surface) per frame, against particles and against the
// reconstruction's resolution, next to the cost of the simulation's step on the same particles. The thesis's bunny
// (assets/scenes/bunny_thesis.json) at 8 particles per cell, grown for more particles, with the surface's defaults
// (resolution 2, smoothing 3); and the smallest of those bunnies at resolutions 1 to 4 (1 to 3 at the quick sizes).
// Every configuration is built first; their steps are timed interleaved (timeInterleaved: warm-up steps, then rounds of runs); then each surface
// is rebuilt from the state its steps left: once untimed (the programs JIT-compile), then in `repeats` rounds, one
// rebuild of each configuration per round, glFinish to glFinish, then `repeats` rounds more with each pass timed
// (PassTimer) for the split between the field and the mesh. Interleaving puts a change in a shared machine's load
// on every configuration alike. Every column is a median over its runs. The summary gives the surface's share of a
// frame: a frame at 30 Hz takes ceil((1/30 s) / dt) steps.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
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
  surface.reconstruct(simulation.particleView());
  const auto sum = [&](const std::vector<std::string>& passes) {
    double totalMs = 0;
    for (const gl::PassTimer::PassTime& time : surface.passTimes()) {
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

// A configuration with its simulation and its surface, built before anything is timed so that every timing can
// take them in rounds (a change in the machine's load falls on all of them alike).
struct SurfaceCase {
  SurfaceSetup setup;
  std::string label;
  CsvTable::Row* row = nullptr;
  std::size_t particles = 0;
  std::unique_ptr<Simulation> simulation;
  std::unique_ptr<surface::SurfaceReconstruction> surface;
  StepTiming step;
  std::vector<double> surfaceWallMs;
  PhaseMs phases;
};

}  // namespace

PlannedWork planSurface(const BenchRun& run) {
  PlannedWork work;
  const Sizes& sizes = run.sizes();
  // Each configuration's steps, then its surface rebuilt once untimed and twice per repeat (whole, and pass by pass),
  // a rebuild about a step's work on the same particles.
  const double steps = plannedSteps(sizes.timing) + 1 + 2.0 * sizes.timing.repeats;
  for (const double particles : sizes.surfaceParticles) work.add(particles, steps);
  work.add(sizes.surfaceParticles.front(), steps, 1, int(sizes.surfaceResolutions.size()));
  return work;
}

void measureSurface(BenchRun& run) {
  CsvTable table({"series", "particles", "resolution", "smoothing", "grid_nodes", "grid_mib", "vertices", "triangles",
                  "repeats", "surface_ms", "surface_ms_min", "surface_ms_max", "bounds_ms", "splat_ms", "mesh_ms",
                  "ms_per_step", "steps_per_frame", "surface_share_of_frame", "transfer_shape", "status", "renderer"});
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

  // Every configuration built before anything is timed.
  std::vector<SurfaceCase> cases;
  for (const SurfaceSetup& setup : setups) {
    SurfaceCase& c = cases.emplace_back();
    c.setup = setup;
    c.label = "surface, " + setup.series + ", bunny scale " + fixed(setup.bunny.scale, 3) + ", resolution " +
              fixed(setup.resolution, 0);
    c.row = &table.addRow();
    c.row->setText("series", setup.series).set("resolution", setup.resolution).setText("renderer", run.renderer());
    try {
      Scene scene = bunnies.scene(setup.bunny);
      scene.surface.resolution = setup.resolution;
      c.row->set("smoothing", scene.surface.smoothing);
      const std::vector<ParticleSeed> seeds = sampleBodies(scene);
      c.particles = seeds.size();
      c.row->setCount("particles", std::int64_t(seeds.size()));
      c.simulation = std::make_unique<Simulation>(scene, seeds, run.gl());
      c.surface = std::make_unique<surface::SurfaceReconstruction>(scene, seeds, run.gl());
      run.progress(c.label + ": " + grouped(seeds.size()) + " particles");
    } catch (const InputError& error) {
      c.row->setText("status", "skipped");
      run.progress(c.label + ": skipped: " + error.what());
      c.simulation.reset();
      c.surface.reset();
    }
  }
  const auto builtCases = [&] {
    std::vector<SurfaceCase*> built;
    for (SurfaceCase& c : cases) {
      if (c.simulation && c.surface) built.push_back(&c);
    }
    return built;
  };

  // The steps, interleaved as every table's are; then each surface rebuilt from the state its steps left.
  const std::vector<SurfaceCase*> stepped = builtCases();
  std::vector<Simulation*> simulations;
  for (SurfaceCase* c : stepped) simulations.push_back(c->simulation.get());
  run.progress("stepping " + std::to_string(simulations.size()) + " configurations interleaved");
  const std::vector<InterleavedTiming> steps = timeInterleaved(simulations, sizes.timing);
  for (std::size_t k = 0; k < stepped.size(); ++k) {
    if (steps[k].unstable.empty()) {
      stepped[k]->step = steps[k].timing;
      continue;
    }
    stepped[k]->row->setText("status", "unstable");
    run.progress(stepped[k]->label + ": unstable: " + steps[k].unstable);
    stepped[k]->surface.reset();
  }
  for (SurfaceCase* c : builtCases()) {
    try {
      c->surface->reconstruct(c->simulation->particleView());
      glFinish();
    } catch (const InputError& error) {  // the frame's grid is larger than the driver's storage buffers
      c->row->setText("status", "skipped");
      run.progress(c->label + ": skipped: " + error.what());
      c->surface.reset();
    }
  }

  const int repeats = sizes.timing.repeats;
  run.progress("rebuilding " + std::to_string(builtCases().size()) + " surfaces interleaved, " +
               std::to_string(repeats) + " rounds whole and " + std::to_string(repeats) + " pass by pass");
  for (int repeat = 0; repeat < repeats; ++repeat) {
    for (SurfaceCase* c : builtCases()) {
      const auto start = Clock::now();
      c->surface->reconstruct(c->simulation->particleView());
      glFinish();
      c->surfaceWallMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    }
  }
  for (int repeat = 0; repeat < repeats; ++repeat) {
    for (SurfaceCase* c : builtCases()) timePhases(*c->surface, *c->simulation, c->phases);
  }

  std::string summary;
  for (SurfaceCase* c : builtCases()) {
    const surface::SurfaceStats& stats = c->surface->stats();
    const double surfaceMs = median(c->surfaceWallMs);
    const double stepsPerFrame = std::ceil(1 / kFrameRateHz / c->simulation->scene().time.dtS - 1e-9);
    const double share = surfaceMs / (surfaceMs + stepsPerFrame * c->step.medianMs);
    c->row->setCount("grid_nodes", std::int64_t(stats.gridNodes.x) * stats.gridNodes.y * stats.gridNodes.z)
        .set("grid_mib", double(stats.gridBytes) / (1024.0 * 1024.0))
        .setCount("vertices", std::int64_t(stats.vertices))
        .setCount("triangles", std::int64_t(stats.triangles))
        .setCount("repeats", repeats)
        .set("surface_ms", surfaceMs)
        .set("surface_ms_min", *std::min_element(c->surfaceWallMs.begin(), c->surfaceWallMs.end()))
        .set("surface_ms_max", *std::max_element(c->surfaceWallMs.begin(), c->surfaceWallMs.end()))
        .set("bounds_ms", median(c->phases.bounds))
        .set("splat_ms", median(c->phases.splat))
        .set("mesh_ms", median(c->phases.mesh))
        .set("ms_per_step", c->step.medianMs)
        .set("steps_per_frame", stepsPerFrame)
        .set("surface_share_of_frame", share)
        .setText("transfer_shape", chosenTransferShape(*c->simulation))
        .setText("status", "ok");
    run.progress(c->label + ": surface " + fixed(surfaceMs, 1) + " ms (" + grouped(stats.triangles) +
                 " triangles), a step " + fixed(c->step.medianMs, 1) + " ms");
    if (c->setup.series == "particles") {
      summary += (summary.empty() ? "" : "; ") + grouped(c->particles) + " particles " + fixed(surfaceMs, 1) +
                 " ms = " + fixed(surfaceMs / c->step.medianMs, 2) + " steps, " + fixed(100 * share, 1) +
                 "% of a frame";
    }
  }
  run.write(table, "surface");
  if (!summary.empty()) {
    run.addSummary("surface (resolution 2, smoothing 3), the thesis bunny at 8 per cell, per frame: " + summary);
  }
}

}  // namespace firn::bench
