// tradeoff.csv: the speed/accuracy trade on a problem with a known answer, the elastic bar (ElasticBar.h): per
// configuration (kernel, transfer, atomics, particle volumes, dt, particles per cell, cell size, integrator), the
// error of its period against T/√κ, how much of its amplitude it keeps, and the cost of a simulated second. The
// semi-implicit rows step 1, 4, 16 and 64 times the elastic bound h / c (the bar's period is 36 h / c: 16 and 64
// cannot resolve it, and show how a long step damps what it cannot resolve). Each row also gives the energy audit's
// drift per simulated second (sim/EnergyAudit.h), which a scene without a reference still has; the baseline's budget
// over time goes to energy.csv, for energy.png. The summary gives the Pareto front.
#include <algorithm>
#include <cmath>
#include <functional>

#include "ElasticBar.h"
#include "Error.h"
#include "Experiments.h"

namespace firn::bench {

namespace {

// The first steps of a tradeoff run are left out of its time: the first dispatch of each program compiles it.
constexpr std::size_t kTradeoffWarmupSteps = 3;
// A bar whose vibration grows by more than this over the periods measured is going unstable, however slowly:
// "growing", and off the Pareto front. (The peaks are sampled once per step and carry the higher modes that
// the slabs' start excites. Measured over 2 periods: 0.92–0.997 for APIC and PIC/FLIP where stable, 0.70 for
// PIC, 0.29 with one particle per cell; 1.13–1.25 where the step was too long but the watchdog not yet tripped.)
constexpr double kAmplitudeGrowthTolerance = 1.02;

struct TradeoffCase {
  std::string name;
  BarSetup setup;
};

// A baseline, each factor varied alone from it, and three combinations a user might pick: a cheap preview, a
// production setting and a validation run.
std::vector<TradeoffCase> tradeoffCases(BenchSize size, int periods) {
  BarSetup baseline;
  baseline.model = "fixed_corotated";
  baseline.dtFraction = 0.5;
  baseline.periods = periods;
  const auto with = [&](const std::string& name, const std::function<void(BarSetup&)>& change) {
    BarSetup setup = baseline;
    change(setup);
    return TradeoffCase{name, setup};
  };
  const auto unchanged = [](BarSetup&) {};
  const auto semiImplicit = [&](double elasticBounds) {
    return with("semi_implicit_dt_" + formatNumber(elasticBounds), [elasticBounds](BarSetup& s) {
      s.integrator = "semi_implicit";
      s.dtFraction = elasticBounds;
    });
  };
  if (size == BenchSize::Tiny) {
    baseline.cellsAlongBar = 12;
    return {with("baseline", unchanged), with("float_atomics", [](BarSetup& s) { s.atomics = "float"; }),
            semiImplicit(4)};
  }
  std::vector<TradeoffCase> cases = {
      with("baseline", unchanged),
      with("cubic", [](BarSetup& s) { s.kernel = "cubic"; }),
      with("flip_0.95", [](BarSetup& s) { s.transfer = "pic_flip"; }),
      with("pic", [](BarSetup& s) {
        s.transfer = "pic_flip";
        s.flipRatio = 0;
      }),
      with("float_atomics", [](BarSetup& s) { s.atomics = "float"; }),
      with("material_volumes", [](BarSetup& s) { s.particleVolume = "material_density"; }),
      with("dt_0.25", [](BarSetup& s) { s.dtFraction = 0.25; }),
      with("dt_0.9", [](BarSetup& s) { s.dtFraction = 0.9; }),
      with("ppc_1", [](BarSetup& s) { s.particlesPerCell = 1; }),
      with("h_L12", [](BarSetup& s) { s.cellsAlongBar = 12; }),
      // PIC/FLIP's energy grows on this bar at half the bound with h = L/12 (measured); 0.4 keeps it stable.
      with("preview", [](BarSetup& s) {
        s.transfer = "pic_flip";
        s.dtFraction = 0.4;
        s.cellsAlongBar = 12;
      }),
      with("production", [](BarSetup& s) { s.cellsAlongBar = 24; }),
      semiImplicit(1),
      semiImplicit(4),
      semiImplicit(16),
      semiImplicit(64),
      // β = 1/2 evaluates the force halfway along the step: for an oscillator of ω at ω dt = 2π/9 (4 h / c on the
      // baseline bar) the period lengthens by 5% where β = 1 lengthens it by 15%, and a step keeps 0.90 of the
      // amplitude where β = 1 keeps 0.82; as ω dt grows, β = 1/2 still damps (the step's gain tends to 0).
      with("semi_implicit_dt_4_ratio_0.5", [](BarSetup& s) {
        s.integrator = "semi_implicit";
        s.dtFraction = 4;
        s.implicitRatio = 0.5;
      }),
  };
  if (size == BenchSize::Quick) return cases;
  // Bars of 10,000 to 35,000 particles: together a minute of llvmpipe's time, most of what the quick sizes allow.
  cases.insert(cases.end(), {
      with("ppc_27", [](BarSetup& s) { s.particlesPerCell = 27; }),
      with("h_L36", [](BarSetup& s) { s.cellsAlongBar = 36; }),
      with("validation", [](BarSetup& s) {
        s.kernel = "cubic";
        s.dtFraction = 0.25;
        s.particlesPerCell = 27;
        s.cellsAlongBar = 36;
      }),
      // The same 4 h / c step on a bar of twice the cells: 18 steps per period where the baseline bar has 9.
      with("semi_implicit_dt_4_h_L36", [](BarSetup& s) {
        s.integrator = "semi_implicit";
        s.dtFraction = 4;
        s.cellsAlongBar = 36;
      }),
      // β = 1/2 at 18 steps per period, ω dt = 2π/18, where the step's own period error is 1.4%.
      with("semi_implicit_dt_4_h_L36_ratio_0.5", [](BarSetup& s) {
        s.integrator = "semi_implicit";
        s.dtFraction = 4;
        s.cellsAlongBar = 36;
        s.implicitRatio = 0.5;
      }),
  });
  if (size == BenchSize::Default) {
    cases.push_back(with("ppc_64", [](BarSetup& s) { s.particlesPerCell = 64; }));
    cases.push_back(with("h_L72", [](BarSetup& s) { s.cellsAlongBar = 72; }));
    cases.push_back(with("validation_L72", [](BarSetup& s) {
      s.kernel = "cubic";
      s.dtFraction = 0.25;
      s.particlesPerCell = 27;
      s.cellsAlongBar = 72;
    }));
  }
  return cases;
}

struct TradeoffResult {
  CsvTable::Row* row;
  std::string configuration;
  double costMs;  // per simulated second
  double error;
};

// Marks each stable result's row pareto 1 or 0 and returns the front, cheapest first. On the front: no other
// configuration is at once no more costly and no less accurate, and better in one.
std::vector<const TradeoffResult*> paretoFront(const std::vector<TradeoffResult>& results) {
  std::vector<const TradeoffResult*> front;
  for (const TradeoffResult& result : results) {
    const bool dominated = std::any_of(results.begin(), results.end(), [&](const TradeoffResult& other) {
      return other.costMs <= result.costMs && other.error <= result.error &&
             (other.costMs < result.costMs || other.error < result.error);
    });
    result.row->setCount("pareto", dominated ? 0 : 1);
    if (!dominated) front.push_back(&result);
  }
  std::sort(front.begin(), front.end(),
            [](const TradeoffResult* a, const TradeoffResult* b) { return a->costMs < b->costMs; });
  return front;
}

}  // namespace

PlannedWork planTradeoff(const BenchRun& run) {
  PlannedWork work;
  for (const TradeoffCase& configuration : tradeoffCases(run.options().size, run.sizes().barPeriods)) {
    const BarSetup& setup = configuration.setup;
    if (setup.atomics == "float" && !run.gl().hasFloatAtomics) continue;  // refused before it builds
    const Scene scene = barScene(setup);
    const double cost = (setup.kernel == "cubic" ? 1 : kQuadraticStepCost) *
                        (setup.integrator == "explicit" ? 1 : semiImplicitStepCost(scene));
    work.add(double(sampleBodies(scene).size()), barMaxSteps(setup, scene.time.dtS), cost);
  }
  return work;
}

void measureTradeoff(BenchRun& run) {
  CsvTable table({"configuration", "integrator", "implicit_ratio", "kernel", "transfer", "flip_ratio", "atomics",
                  "transfer_shape", "dt_s", "dt_fraction",
                  "particles_per_cell", "cell_size_m", "particles", "steps", "ms_per_step",
                  "ms_per_simulated_second", "period_s", "error", "signed_error", "uncorrected_error",
                  "amplitude_retained", "energy_drift_per_s", "solver_iterations", "kappa", "pareto", "status",
                  "renderer"});
  // The baseline's energy budget over time, in stats.csv's columns (io/EnergyPlot.h draws it).
  CsvTable energy({"time_s", "kinetic_energy_j", "potential_energy_j", "elastic_energy_j", "bodies_kinetic_energy_j",
                   "bodies_potential_energy_j", "step_energy_j", "walls_removed_j", "dissipated_energy_j"});
  std::vector<TradeoffResult> results;
  const double analyticPeriodS = barAnalyticPeriodS();
  for (const TradeoffCase& configuration : tradeoffCases(run.options().size, run.sizes().barPeriods)) {
    const BarSetup& setup = configuration.setup;
    CsvTable::Row& row = table.addRow();
    const std::string transfer = setup.transfer == "apic" ? "apic" : setup.flipRatio == 0 ? "pic" : "pic_flip";
    row.setText("configuration", configuration.name)
        .setText("integrator", setup.integrator)
        .setText("kernel", setup.kernel)
        .setText("transfer", transfer)
        .setText("atomics", setup.atomics)
        .set("dt_fraction", setup.dtFraction)
        .set("particles_per_cell", setup.particlesPerCell)
        .set("cell_size_m", kBarLengthM / setup.cellsAlongBar)
        .setText("renderer", run.renderer());
    if (setup.integrator != "explicit") row.set("implicit_ratio", setup.implicitRatio);
    if (transfer != "apic") row.set("flip_ratio", setup.flipRatio);
    try {
      const BarVibration bar = measureBarVibration(setup, run.gl());
      row.set("dt_s", bar.dtS)
          .setCount("particles", std::int64_t(bar.particles))
          .setText("transfer_shape", bar.transferShape);
      const std::vector<double> timedMs(
          bar.stepWallMs.begin() + std::ptrdiff_t(std::min(kTradeoffWarmupSteps, bar.stepWallMs.size() - 1)),
          bar.stepWallMs.end());
      const double msPerStep = median(timedMs);
      row.setCount("steps", std::int64_t(timedMs.size()))
          .set("ms_per_step", msPerStep)
          .set("ms_per_simulated_second", msPerStep / bar.dtS)
          .set("kappa", bar.kappa)
          .set("amplitude_retained", bar.amplitudeRetained)
          .set("energy_drift_per_s", bar.energyDriftPerS);
      if (configuration.name == "baseline") {
        for (const auto& [timeS, budget] : bar.energy) {
          energy.addRow()
              .set("time_s", timeS)
              .set("kinetic_energy_j", budget.kineticJ)
              .set("potential_energy_j", budget.potentialJ)
              .set("elastic_energy_j", budget.elasticJ)
              .set("bodies_kinetic_energy_j", budget.bodiesKineticJ)
              .set("bodies_potential_energy_j", budget.bodiesPotentialJ)
              .set("step_energy_j", budget.stepTermJ)
              .set("walls_removed_j", budget.wallsRemovedJ)
              .set("dissipated_energy_j", budget.dissipatedJ);
        }
      }
      if (setup.integrator != "explicit") row.set("solver_iterations", bar.meanSolverIterations);
      if (bar.periodS <= 0) {
        row.setText("status", "no_period");
        run.progress("tradeoff, " + configuration.name + ": no full period within the steps allowed; amplitude kept " +
                     fixed(bar.amplitudeRetained, 3));
        continue;
      }
      const double signedError = bar.periodS / (analyticPeriodS / std::sqrt(bar.kappa)) - 1;
      row.set("period_s", bar.periodS)
          .set("error", std::abs(signedError))
          .set("signed_error", signedError)
          .set("uncorrected_error", std::abs(bar.periodS / analyticPeriodS - 1));
      if (bar.amplitudeRetained > kAmplitudeGrowthTolerance) {
        row.setText("status", "growing");
      } else {
        row.setText("status", "ok");
        results.push_back({&row, configuration.name, msPerStep / bar.dtS, std::abs(signedError)});
      }
      run.progress("tradeoff, " + configuration.name + ": " + grouped(bar.particles) + " particles, " +
                   fixed(msPerStep, 2) + " ms per step, " + fixed(msPerStep / bar.dtS / 1e3, 2) +
                   " s per simulated second, period error " + fixed(100 * signedError, 2) + "%, amplitude kept " +
                   fixed(bar.amplitudeRetained, 3) +
                   (setup.integrator == "explicit" ? std::string()
                                                   : ", " + fixed(bar.meanSolverIterations, 1) + " iterations per step"));
    } catch (const SimulationError& error) {
      row.setText("status", "unstable");
      run.progress("tradeoff, " + configuration.name + ": unstable: " + error.what());
    } catch (const InputError& error) {
      row.setText("status", run.inputErrorStatus(setup.atomics));
      run.progress("tradeoff, " + configuration.name + ": " + error.what());
    }
  }
  std::string frontText;
  for (const TradeoffResult* result : paretoFront(results)) {
    frontText += (frontText.empty() ? "" : ", ") + result->configuration + " (" + fixed(result->costMs / 1e3, 2) +
                 " s per simulated s, error " + formatNumber(result->error) + ")";
  }
  run.write(table, "tradeoff");
  run.write(energy, "energy");
  run.addSummary("tradeoff (elastic bar, period error against T/sqrt(kappa)): Pareto front " +
                 (frontText.empty() ? std::string("empty") : frontText));
}

}  // namespace firn::bench
