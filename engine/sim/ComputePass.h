#pragma once
// A compute pass: one shader's program and the rule that says how many invocations a dispatch of it launches.
// Passes are timed by name through a PassTimer when a benchmark asks for it.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gl/Buffer.h"
#include "gl/Program.h"
#include "gl/Query.h"
#include "gl/ShaderLibrary.h"

namespace firn {

// GPU and wall time per pass, summed over the dispatches since timing was switched on. Timing waits for each
// pass (glFinish before and after), so it is for benchmarks, never for production runs; without it a pass only
// runs gl::checkPass, which is free outside debug builds.
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
  gl::TimerQuery query_;
  std::chrono::steady_clock::time_point wallStart_;
  std::vector<PassTime> times_;
};

class ComputePass {
 public:
  enum class Dispatch {
    Once,       // one work group
    Particles,  // one invocation per particle, FIRN_PARTICLE_GROUP_SIZE to a group
    Indirect,   // the work groups a buffer holds (written by an earlier pass)
  };

  ComputePass() = default;
  ComputePass(const gl::ShaderLibrary& library, const std::string& shader, const gl::ShaderOptions& options,
              Dispatch dispatch);

  explicit operator bool() const { return program_.id() != 0; }
  const gl::Program& program() const { return program_; }

  // Sets a uint uniform of the program for the dispatches that follow (a name the compiler dropped is ignored).
  const ComputePass& set(const char* uniform, unsigned value) const;

  void runOnce(PassTimer& timer) const;
  // More groups than one dimension allows (maxWorkGroupsX) are laid out in rows; the shader folds y back into
  // the particle index (common/bindings.glsl, particleInvocationIndex).
  void runOverParticles(std::size_t particles, int maxWorkGroupsX, PassTimer& timer) const;
  // The group counts at `offsetBytes` in `commands` (a glDispatchComputeIndirect record).
  void runIndirect(const gl::Buffer& commands, std::size_t offsetBytes, PassTimer& timer) const;

 private:
  void dispatch(PassTimer& timer, GLuint x, GLuint y) const;

  gl::Program program_;
  Dispatch dispatch_ = Dispatch::Once;
};

}  // namespace firn
