#pragma once
// A compute pass: one shader's program, the buffers it binds before each dispatch (the blocks it declares, from a
// BufferBindings), what it reads and writes of them (its header's declarations: gl/StorageAccess.h), and how many
// work groups a dispatch launches: one, enough for a count of invocations at the program's own work-group size, or
// what a buffer holds (written by an earlier pass). The barrier a dispatch needs after the passes before it is
// placed by the BufferBindings it binds from. Each dispatch is timed under the pass's phase name when a PassTimer is
// enabled.
#include <cstddef>
#include <string>

#include "gl/Buffer.h"
#include "gl/BufferBindings.h"
#include "gl/PassTimer.h"
#include "gl/Program.h"
#include "gl/ShaderLibrary.h"
#include "gl/StorageAccess.h"

namespace firn::gl {

class ComputePass {
 public:
  ComputePass() = default;
  // `phase` names the pass in timings; by default the shader's path. Two programs of one shader (variants) that do
  // different work in a step take different names.
  ComputePass(const ShaderLibrary& library, const std::string& shader, const ShaderOptions& options,
              std::string phase = {});

  explicit operator bool() const { return program_.id() != 0; }
  const Program& program() const { return program_; }
  const std::string& phase() const { return phase_; }
  // What it reads and writes, as its shader's header declares (gl/StorageAccess.h).
  const StorageAccess& access() const { return access_; }

  // Sets a uint uniform of the program for the dispatches that follow (a name the compiler dropped is ignored).
  const ComputePass& set(const char* uniform, unsigned value) const;

  void runOnce(const BufferBindings& buffers, PassTimer& timer) const;
  // One invocation per item, in groups of the program's work-group size (x). More groups than one dimension allows
  // (`maxWorkGroupsX`) are laid out in rows, which the shader folds back into one index.
  void runOver(std::size_t items, int maxWorkGroupsX, const BufferBindings& buffers, PassTimer& timer) const;
  // `groups` work groups, laid out in rows as runOver's.
  void runGroups(std::size_t groups, int maxWorkGroupsX, const BufferBindings& buffers, PassTimer& timer) const;
  // The group counts at `offsetBytes` in `commands` (a glDispatchComputeIndirect record).
  void runIndirect(const Buffer& commands, std::size_t offsetBytes, const BufferBindings& buffers,
                   PassTimer& timer) const;

 private:
  void prepare(const BufferBindings& buffers, const Buffer* commands, PassTimer& timer) const;
  void finish(const BufferBindings& buffers, PassTimer& timer) const;

  Program program_;
  std::string phase_;
  StorageAccess access_;
  GLuint groupSize_ = 1;
};

}  // namespace firn::gl
