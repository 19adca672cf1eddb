#pragma once
// The fixed-step accumulator that keeps physics apart from drawing (Fiedler, "Fix Your Timestep!", 2004):
// wall-clock time, scaled by the simulation speed, is banked each frame and spent in whole steps of the
// scene's dt, so the simulation follows the same sequence of steps at any frame rate. A cap on the steps
// per frame keeps a machine that cannot keep up from spiralling (each frame taking longer, so owing more
// steps, so taking longer still): beyond the cap, the backlog is dropped and the simulation runs slower
// than real time instead.

namespace firn {

class StepAccumulator {
 public:
  // dtS: the scene's step; maxStepsPerFrame ≥ 1.
  StepAccumulator(double dtS, int maxStepsPerFrame);

  // Banks one frame of `frameWallS` seconds at `speed` simulated seconds per wall second and returns how
  // many steps of dt to take now. Negative or non-finite frame times count as zero.
  int stepsForFrame(double frameWallS, double speed = 1.0);

  double dtS() const { return dtS_; }
  int maxStepsPerFrame() const { return maxStepsPerFrame_; }
  // The viewer sets the cap from the measured cost of a step, so physics fits its share of a frame.
  void setMaxStepsPerFrame(int maxStepsPerFrame);
  // Simulated time owed but not yet stepped (less than one dt after any frame).
  double bankedS() const { return bankedS_; }
  // Simulated time given up because of the cap, since construction or reset().
  double droppedS() const { return droppedS_; }
  void reset();

 private:
  double dtS_;
  int maxStepsPerFrame_ = 1;
  double bankedS_ = 0;
  double droppedS_ = 0;
};

}  // namespace firn
