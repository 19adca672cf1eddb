#pragma once
// How a run advances in time (docs/algorithm.md, "Time step"): fixed steps, adaptive ones bounded by the CFL
// condition on the fastest signal, and the smaller steps with which a frame the watchdog rejected is redone.
#include <functional>

#include "scene/Scene.h"

namespace firn {

class SteppingPolicy {
 public:
  // `fastestSignalMPerS`: the largest |v| + c before the first step (the seeds' speeds plus the stiffest wave).
  SteppingPolicy(const Scene& scene, double fastestSignalMPerS);

  // Steps from `fromS` to `toS` through `takeStep(dtS)`, landing on `toS` exactly; returns the count. Fixed dt:
  // equal steps no larger than time.dt. Adaptive (time.adaptive): each step as large as time.cfl times the CFL
  // bound h / (|v| + c) allows, with `fastestSignalAfterStep()` read after each step.
  int advance(double fromS, double toS, const std::function<void(double dtS)>& takeStep,
              const std::function<double()>& fastestSignalAfterStep);

  bool adaptive() const { return adaptive_; }
  // After a rejected frame: halves the steps and returns true, or returns false once `attempt` (from 0) has used
  // up the retries.
  bool shrinkForRetry(int attempt);
  double stepScale() const { return stepScale_; }
  void resetStepScale() { stepScale_ = 1; }

  // The adaptive state a saved or checkpointed simulation carries.
  double fastestSignalMPerS() const { return fastestSignalMPerS_; }
  void setFastestSignalMPerS(double speedMPerS) { fastestSignalMPerS_ = speedMPerS; }

 private:
  double adaptiveDtS() const;

  bool adaptive_;
  double dtS_;
  double cfl_;
  double cellSizeM_;
  double gravityMPerS2_;
  double fastestSignalMPerS_;
  double stepScale_ = 1;
};

}  // namespace firn
