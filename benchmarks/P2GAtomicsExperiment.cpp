// p2g_atomics.csv: how P2G sums, fixed point against float atomics: P2G's time (the sort into the grid's blocks
// and the scatter), and its sums on the reference bunny (falling and spinning) against the same
// contributions added in double on the CPU (P2GReference.h), as relative and absolute errors per node.
#include <stdexcept>

#include "Error.h"
#include "Experiments.h"
#include "P2GReference.h"
#include "sim/Simulation.h"

namespace firn::bench {

namespace {

// The velocity field of the P2G comparison: a falling, spinning bunny, so momentum sums are nonzero and vary
// (at rest they would all be zero, and fixed and float both exact).
constexpr glm::dvec3 kP2GVelocityMPerS{0.0, -3.0, 0.0};
constexpr glm::dvec3 kP2GAngularVelocityRadPerS{0.0, 2.0, 0.0};

}  // namespace

PlannedWork planP2GAtomics(const BenchRun& run) {
  PlannedWork work;
  // Fixed point in tiles and in blocks, and float sums where the driver has them (elsewhere refused before a build).
  work.add(run.sizes().smallestParticles, plannedSteps(run.sizes().timing), 1, run.gl().hasFloatAtomics ? 3 : 2);
  return work;
}

void measureP2GAtomics(BenchRun& run) {
  CsvTable table({"atomics", "transfer_shape", "p2g_ms", "p2g_gpu_ms", "mass_max_rel_error", "mass_rms_rel_error",
                  "momentum_max_rel_error", "momentum_rms_rel_error", "mass_max_error_units",
                  "momentum_max_error_units", "fraction_bits", "resolution_units", "max_contributions", "nodes",
                  "particles", "status", "renderer"});
  std::string summary;
  for (const SumSeries& sums :
       {SumSeries{"fixed", "tiles"}, SumSeries{"fixed", "blocks"}, SumSeries{"float", "tiles"}}) {
    const std::string& atomics = sums.atomics;
    CsvTable::Row& row = table.addRow();
    row.setText("atomics", atomics).setText("transfer_shape", sums.transferShape).setText("renderer", run.renderer());
    try {
      BunnySetup setup = run.referenceBunny();
      setup.atomics = atomics;
      setup.velocityMPerS = kP2GVelocityMPerS;
      setup.angularVelocityRadPerS = kP2GAngularVelocityRadPerS;
      const Scene scene = run.bunnies().scene(setup);
      const std::vector<ParticleSeed> seeds = sampleBodies(scene);
      SimulationOptions options;
      options.transferShapes = sums.transferShape;
      Simulation simulation(scene, seeds, run.gl(), options);
      row.setText("transfer_shape", chosenTransferShape(simulation));
      const FixedPointScale& scale = simulation.fixedPoint();
      const ReferenceGrid reference = referenceParticleToGrid(scene, scale, simulation.snapshot());
      const SumErrorSummary errors =
          summarizeErrors(compareWithReference(simulation.readGridAfterTransfer(), reference, scene, scale));
      const std::vector<PassTiming> timings = timePasses(simulation, run.sizes().timing);
      // P2G is the sort of the particles into the grid's blocks and the scatter: every pass before the grid update.
      PassTiming p2g{"p2g"};
      for (const PassTiming& timing : timings) {
        if (timing.pass != "update_grid" && timing.pass != "g2p") {
          p2g.wallMs += timing.wallMs;
          p2g.gpuMs += timing.gpuMs;
        }
      }
      if (p2g.wallMs == 0) throw std::logic_error("no p2g pass among the timed passes");
      row.set("p2g_ms", p2g.wallMs)
          .set("p2g_gpu_ms", p2g.gpuMs)
          .set("mass_max_rel_error", errors.massMaxRelative)
          .set("mass_rms_rel_error", errors.massRmsRelative)
          .set("momentum_max_rel_error", errors.momentumMaxRelative)
          .set("momentum_rms_rel_error", errors.momentumRmsRelative)
          .set("mass_max_error_units", errors.massMaxUnits)
          .set("momentum_max_error_units", errors.momentumMaxUnits)
          .setCount("max_contributions", errors.maxContributions)
          .setCount("nodes", std::int64_t(errors.nodes))
          .setCount("particles", std::int64_t(seeds.size()))
          .setText("status", "ok");
      if (atomics == "fixed") row.setCount("fraction_bits", scale.fractionBits).set("resolution_units", scale.resolution());
      const std::string line = atomics + " by " + chosenTransferShape(simulation) + ": P2G " + fixed(p2g.wallMs, 2) +
                               " ms, relative error max/RMS mass " + formatNumber(errors.massMaxRelative) + "/" +
                               formatNumber(errors.massRmsRelative) +
                               ", momentum " + formatNumber(errors.momentumMaxRelative) + "/" +
                               formatNumber(errors.momentumRmsRelative);
      run.progress("p2g atomics, " + line);
      summary += (summary.empty() ? "" : "; ") + line;
    } catch (const SimulationError& error) {
      row.setText("status", "unstable");
      run.progress("p2g atomics, " + sums.label() + ": unstable: " + error.what());
    } catch (const InputError& error) {
      row.setText("status", run.inputErrorStatus(atomics));
      run.progress("p2g atomics, " + sums.label() + ": " + error.what());
    }
  }
  run.write(table, "p2g_atomics");
  run.addSummary("p2g atomics (" + fixed(run.bunnies().cellSizeM(), 2) + " m cells, bunny falling at " +
                 fixed(-kP2GVelocityMPerS.y, 0) + " m/s and spinning at " + fixed(kP2GAngularVelocityRadPerS.y, 0) +
                 " rad/s): " + summary);
}

}  // namespace firn::bench
