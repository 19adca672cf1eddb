#pragma once
// GPU and wall time per pass, named by the phase it belongs to, summed over the dispatches since timing was switched
// on. Timing waits for each pass (glFinish before and after), so it is for benchmarks, never for production runs;
// without it a pass only runs gl::checkPass, which is free outside debug builds.
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gl/Query.h"

namespace firn::gl {

class PassTimer {
 public:
  struct PassTime {
    std::string pass;
    double totalMs = 0;      // GPU time from the timer query
    double totalWallMs = 0;  // host time from before the dispatch until glFinish returns
    std::uint64_t dispatches = 0;
  };

  void setEnabled(bool enabled);
  void begin();
  void end(const std::string& pass);
  const std::vector<PassTime>& times() const { return times_; }

 private:
  bool enabled_ = false;
  TimerQuery query_;
  std::chrono::steady_clock::time_point wallStart_;
  std::vector<PassTime> times_;
};

// Host milliseconds from an idle GPU until the commands `work` issues have finished (glFinish before and after): for
// timing a few dispatches once, as a run's choice of transfer shape does.
double msToFinish(const std::function<void()>& work);

}  // namespace firn::gl
