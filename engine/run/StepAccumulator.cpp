#include "run/StepAccumulator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace firn {

StepAccumulator::StepAccumulator(double dtS, int maxStepsPerFrame) : dtS_(dtS) {
  if (!(dtS > 0)) throw std::invalid_argument("StepAccumulator: dt must be positive");
  setMaxStepsPerFrame(maxStepsPerFrame);
}

void StepAccumulator::setMaxStepsPerFrame(int maxStepsPerFrame) {
  if (maxStepsPerFrame < 1) throw std::invalid_argument("StepAccumulator: the cap must be at least one step");
  maxStepsPerFrame_ = maxStepsPerFrame;
}

int StepAccumulator::stepsForFrame(double frameWallS, double speed) {
  const double owedS = frameWallS * speed;
  if (std::isfinite(owedS) && owedS > 0) bankedS_ += owedS;
  // A relative tolerance keeps a bank of exactly n·dt, summed from rounded frame times, from paying n − 1.
  const double owedSteps = std::floor(bankedS_ / dtS_ + 1e-9);
  if (owedSteps > maxStepsPerFrame_) {
    // Spend the cap, keep the fraction of a step that is left over, give up the rest.
    const double keptS = std::max(0.0, bankedS_ - owedSteps * dtS_);
    droppedS_ += bankedS_ - maxStepsPerFrame_ * dtS_ - keptS;
    bankedS_ = keptS;
    return maxStepsPerFrame_;
  }
  const int steps = static_cast<int>(owedSteps);
  bankedS_ = std::max(0.0, bankedS_ - steps * dtS_);
  return steps;
}

void StepAccumulator::reset() {
  bankedS_ = 0;
  droppedS_ = 0;
}

}  // namespace firn
