#include "sim/SteppingPolicy.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace firn {

namespace {

// A frame the watchdog rejects is redone with steps half as large, up to this many times.
constexpr int kAdaptiveRetries = 3;

}  // namespace

SteppingPolicy::SteppingPolicy(const Scene& scene, double fastestSignalMPerS)
    : adaptive_(scene.time.adaptive), dtS_(scene.time.dtS), cfl_(scene.time.cfl), cellSizeM_(scene.grid.cellSizeM),
      gravityMPerS2_(glm::length(scene.gravityMPerS2)), fastestSignalMPerS_(fastestSignalMPerS) {}

// Each adaptive step is the largest that the CFL condition on the fastest signal, max over particles of |v| + c
// (the particle's speed plus its material's wave speed in its present, hardened state; semi-implicit steps: |v|
// alone), allows, times time.cfl, and no larger than time.dt. Gravity may add |g| dt during the step.
double SteppingPolicy::adaptiveDtS() const {
  const double cfl = cfl_ * stepScale_;
  const double speedMPerS = fastestSignalMPerS_ + gravityMPerS2_ * dtS_;
  double dtS = dtS_ * stepScale_;
  if (speedMPerS > 0) dtS = std::min(dtS, cfl * cellSizeM_ / speedMPerS);
  return dtS;
}

int SteppingPolicy::advance(double fromS, double toS, const std::function<void(double dtS)>& takeStep,
                            const std::function<double()>& fastestSignalAfterStep) {
  if (adaptive_) {
    int steps = 0;
    double nowS = fromS;
    while (toS - nowS > 1e-12 * toS) {
      const double remainingS = toS - nowS;
      double dtS = adaptiveDtS();
      // Land on the frame exactly, without a sliver of a last step: the last two steps share what is left.
      if (remainingS <= dtS) {
        dtS = remainingS;
      } else if (remainingS < 2 * dtS) {
        dtS = remainingS / 2;
      }
      takeStep(dtS);
      nowS += dtS;
      fastestSignalMPerS_ = fastestSignalAfterStep();
      ++steps;
    }
    return steps;
  }
  const double remainingS = toS - fromS;
  if (remainingS <= 0) return 0;
  // Equal steps, none larger than dt; the tolerance keeps an exact multiple from taking one step more.
  const int steps = std::max(1, static_cast<int>(std::ceil(remainingS / dtS_ - 1e-9)));
  const double dtS = remainingS / steps;
  for (int i = 0; i < steps; ++i) takeStep(dtS);
  return steps;
}

bool SteppingPolicy::shrinkForRetry(int attempt) {
  if (attempt >= kAdaptiveRetries) return false;
  stepScale_ /= 2;
  return true;
}

}  // namespace firn
