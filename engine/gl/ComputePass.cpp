#include "gl/ComputePass.h"

#include <optional>
#include <utility>

namespace firn::gl {

ComputePass::ComputePass(const ShaderLibrary& library, const std::string& shader, const ShaderOptions& options,
                         std::string phase)
    : program_(Program::compute(library, shader, options)),
      phase_(phase.empty() ? shader : std::move(phase)),
      groupSize_(GLuint(program_.workGroupSize().x)) {
  if (const std::optional<DeclaredAccess> declared = declaredAccess(shader, library.file(shader))) {
    access_ = resolveAccess(shader, *declared, program_, library.preprocess(shader, options).text);
  } else {
    access_ = undeclaredAccess(shader, program_);
  }
}

const ComputePass& ComputePass::set(const char* uniform, unsigned value) const {
  program_.use();
  program_.set(uniform, value);
  return *this;
}

void ComputePass::prepare(const BufferBindings& buffers, const Buffer* commands, PassTimer& timer) const {
  buffers.beforePass(access_, commands);
  program_.use();
  buffers.bindFor(program_);
  timer.begin();
}

void ComputePass::finish(const BufferBindings& buffers, PassTimer& timer) const {
  timer.end(phase_);
  buffers.afterPass(access_, phase_);
}

void ComputePass::runOnce(const BufferBindings& buffers, PassTimer& timer) const {
  prepare(buffers, nullptr, timer);
  glDispatchCompute(1, 1, 1);
  finish(buffers, timer);
}

void ComputePass::runOver(std::size_t items, int maxWorkGroupsX, const BufferBindings& buffers,
                          PassTimer& timer) const {
  runGroups((items + groupSize_ - 1) / groupSize_, maxWorkGroupsX, buffers, timer);
}

void ComputePass::runGroups(std::size_t groups, int maxWorkGroupsX, const BufferBindings& buffers,
                            PassTimer& timer) const {
  const GLuint count = static_cast<GLuint>(groups);
  const GLuint maxX = static_cast<GLuint>(maxWorkGroupsX);
  prepare(buffers, nullptr, timer);
  if (count <= maxX) {
    glDispatchCompute(count, 1, 1);
  } else {
    glDispatchCompute(maxX, (count + maxX - 1) / maxX, 1);
  }
  finish(buffers, timer);
}

void ComputePass::runIndirect(const Buffer& commands, std::size_t offsetBytes, const BufferBindings& buffers,
                              PassTimer& timer) const {
  prepare(buffers, &commands, timer);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, commands.id());
  glDispatchComputeIndirect(static_cast<GLintptr>(offsetBytes));
  finish(buffers, timer);
}

}  // namespace firn::gl
