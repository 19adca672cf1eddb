// The viewer's fixed-step accumulator: steps per frame for given frame times, and the cap.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "run/StepAccumulator.h"

namespace firn {
namespace {

TEST(StepAccumulator, PaysWholeStepsAndCarriesTheRemainder) {
  StepAccumulator accumulator(1e-3, 100);
  // 2.5 ms owes two steps and carries half a step; the next 2.5 ms makes 3 ms: three steps, nothing left.
  EXPECT_EQ(accumulator.stepsForFrame(2.5e-3), 2);
  EXPECT_NEAR(accumulator.bankedS(), 0.5e-3, 1e-15);
  EXPECT_EQ(accumulator.stepsForFrame(2.5e-3), 3);
  EXPECT_NEAR(accumulator.bankedS(), 0.0, 1e-15);
  EXPECT_EQ(accumulator.stepsForFrame(0.4e-3), 0);
}

TEST(StepAccumulator, FollowsWallClockAtAnyFrameRate) {
  // One simulated second at 60 Hz and at 144 Hz is 1,000 steps of 1 ms either way. Frame times of 1/60 s
  // are not multiples of dt, so single frames pay 16 or 17 steps; the total may lag by the one step still
  // banked, never more.
  for (double frameRateHz : {30.0, 60.0, 144.0}) {
    StepAccumulator accumulator(1e-3, 1000);
    int steps = 0;
    const int frames = static_cast<int>(frameRateHz);
    for (int frame = 0; frame < frames; ++frame) steps += accumulator.stepsForFrame(1.0 / frameRateHz);
    EXPECT_GE(steps, 999) << frameRateHz << " Hz";
    EXPECT_LE(steps, 1000) << frameRateHz << " Hz";
    EXPECT_EQ(accumulator.droppedS(), 0.0);
  }
}

TEST(StepAccumulator, SpeedScalesSimulatedTime) {
  StepAccumulator half(1e-3, 1000);
  StepAccumulator twice(1e-3, 1000);
  int halfSteps = 0, twiceSteps = 0;
  for (int frame = 0; frame < 100; ++frame) {
    halfSteps += half.stepsForFrame(0.01, 0.5);   // 1 s of wall time at half speed: 0.5 s simulated
    twiceSteps += twice.stepsForFrame(0.01, 2.0);  // … at double speed: 2 s simulated
  }
  EXPECT_NEAR(halfSteps, 500, 1);
  EXPECT_NEAR(twiceSteps, 2000, 1);
}

TEST(StepAccumulator, CapsStepsPerFrameAndDropsTheBacklog) {
  // A slow machine: each frame takes 0.1 s of wall time, which would owe 100 steps of 1 ms. With a cap of 20,
  // every frame pays 20 and gives up the other 80 ms instead of owing them to the next frame (which would
  // take longer still: the spiral the cap prevents).
  StepAccumulator accumulator(1e-3, 20);
  for (int frame = 1; frame <= 10; ++frame) {
    EXPECT_EQ(accumulator.stepsForFrame(0.1), 20) << "frame " << frame;
    EXPECT_LT(accumulator.bankedS(), 1e-3);
    EXPECT_NEAR(accumulator.droppedS(), frame * 0.08, 1e-9);
  }
  // Once frames are fast again, the accumulator is back to real time at once, with no debt to pay.
  EXPECT_LE(accumulator.stepsForFrame(1.0 / 60), 17);
}

TEST(StepAccumulator, IgnoresNegativeAndNonFiniteFrameTimes) {
  StepAccumulator accumulator(1e-3, 20);
  EXPECT_EQ(accumulator.stepsForFrame(-1.0), 0);
  EXPECT_EQ(accumulator.stepsForFrame(std::numeric_limits<double>::quiet_NaN()), 0);
  EXPECT_EQ(accumulator.stepsForFrame(std::numeric_limits<double>::infinity()), 0);
  EXPECT_EQ(accumulator.bankedS(), 0.0);
  EXPECT_EQ(accumulator.stepsForFrame(3e-3), 3);
}

TEST(StepAccumulator, ResetForgetsBankAndDrops) {
  StepAccumulator accumulator(1e-3, 2);
  accumulator.stepsForFrame(1.0);
  accumulator.reset();
  EXPECT_EQ(accumulator.bankedS(), 0.0);
  EXPECT_EQ(accumulator.droppedS(), 0.0);
  EXPECT_THROW(StepAccumulator(0.0, 1), std::invalid_argument);
  EXPECT_THROW(StepAccumulator(1e-3, 0), std::invalid_argument);
}

}  // namespace
}  // namespace firn
