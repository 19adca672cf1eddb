#pragma once
// How a semi-implicit solve ended (sim/ImplicitSolver.h), and when one failed: what the watchdog's message
// (sim/Diagnostics.h) and the stats need of it, without the solver's GL parts.
#include <cstdint>

namespace firn {

// How a step's solve ended.
struct SolveReport {
  int iterations = 0;   // conjugate residual iterations taken
  double residual = 0;  // the relative residual at the end, ‖r‖ / ‖M v*‖ in the P⁻¹ norm (NaN if it became non-finite)
};

// A solve that ends above this many times its tolerance is a failure the watchdog reports (exit 3): the velocities
// are off by more than a hundredth of the tolerance's reference, and the step is no longer the one asked for.
constexpr double kSolverFailureFactor = 100;

// The first solve that failed, and in which step.
struct SolverFailure {
  std::uint64_t step = 0;
  SolveReport report;
};

}  // namespace firn
