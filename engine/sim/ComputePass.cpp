#include "sim/ComputePass.h"

#include <algorithm>
#include <stdexcept>

#include "gl/Debug.h"
#include "sim/GpuLayout.h"

namespace firn {

void PassTimer::setEnabled(bool enabled) {
  enabled_ = enabled;
  times_.clear();
}

void PassTimer::begin() {
  if (!enabled_) return;
  glFinish();
  query_.begin();
  wallStart_ = std::chrono::steady_clock::now();
}

void PassTimer::end(const std::string& pass) {
  gl::checkPass(pass.c_str());
  if (!enabled_) return;
  query_.end();
  glFinish();
  const double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wallStart_).count();
  auto entry = std::find_if(times_.begin(), times_.end(), [&](const PassTime& time) { return time.pass == pass; });
  if (entry == times_.end()) entry = times_.insert(times_.end(), PassTime{pass});
  entry->totalMs += double(query_.elapsedNanoseconds()) * 1e-6;
  entry->totalWallMs += wallMs;
  ++entry->dispatches;
}

ComputePass::ComputePass(const gl::ShaderLibrary& library, const std::string& shader, const gl::ShaderOptions& options,
                         Dispatch dispatch)
    : program_(gl::Program::compute(library, shader, options)), dispatch_(dispatch) {}

void ComputePass::dispatch(PassTimer& timer, GLuint x, GLuint y) const {
  program_.use();
  timer.begin();
  glDispatchCompute(x, y, 1);
  timer.end(program_.name());
}

const ComputePass& ComputePass::set(const char* uniform, unsigned value) const {
  program_.use();
  program_.set(uniform, value);
  return *this;
}

void ComputePass::runOnce(PassTimer& timer) const {
  if (dispatch_ != Dispatch::Once) throw std::logic_error(program_.name() + " is not a single-group pass");
  dispatch(timer, 1, 1);
}

void ComputePass::runOverParticles(std::size_t particles, int maxWorkGroupsX, PassTimer& timer) const {
  if (dispatch_ != Dispatch::Particles) throw std::logic_error(program_.name() + " is not a particle pass");
  const GLuint groups = static_cast<GLuint>((particles + FIRN_PARTICLE_GROUP_SIZE - 1) / FIRN_PARTICLE_GROUP_SIZE);
  const GLuint maxX = static_cast<GLuint>(maxWorkGroupsX);
  if (groups <= maxX) {
    dispatch(timer, groups, 1);
  } else {
    dispatch(timer, maxX, (groups + maxX - 1) / maxX);
  }
}

void ComputePass::runIndirect(const gl::Buffer& commands, std::size_t offsetBytes, PassTimer& timer) const {
  if (dispatch_ != Dispatch::Indirect) throw std::logic_error(program_.name() + " is not an indirect pass");
  program_.use();
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, commands.id());
  timer.begin();
  glDispatchComputeIndirect(static_cast<GLintptr>(offsetBytes));
  timer.end(program_.name());
}

}  // namespace firn
