// A pass binds the blocks its program declares, from the buffers the parts publish (gl/BufferBindings.h): the
// declared bindings are read from the linked program, and a block that nothing provides is an error naming the
// program and the binding, not a dispatch over whatever an earlier call left bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "GlTest.h"
#include "gl/BufferBindings.h"
#include "gl/ComputePass.h"
#include "surface/SurfaceLayout.h"

namespace {

TEST(BufferBindings, ProgramsReportTheBlocksTheyDeclare) {
  firn::test::glContext();
  const firn::gl::ComputePass scan(firn::gl::ShaderLibrary(), "surface/scan_reduce.comp", {});
  std::vector<GLuint> storage = scan.program().storageBindings();
  std::sort(storage.begin(), storage.end());
  EXPECT_EQ(storage, (std::vector<GLuint>{FIRN_BINDING_SCAN_VALUES, FIRN_BINDING_SCAN_SUMS}));
  // The group size the pass dispatches by is the program's own (surface_common.glsl's FIRN_PARTICLE_GROUP_SIZE).
  EXPECT_EQ(scan.program().workGroupSize().x, FIRN_PARTICLE_GROUP_SIZE);
}

TEST(BufferBindings, ABlockNothingProvidesIsAnErrorNamingProgramAndBinding) {
  firn::test::glContext();
  const firn::gl::ComputePass scan(firn::gl::ShaderLibrary(), "surface/scan_reduce.comp", {});
  const firn::gl::Buffer values(64 * sizeof(GLuint) * 2);
  firn::gl::BufferBindings buffers;
  buffers.storage(FIRN_BINDING_SCAN_VALUES, values);  // the sums are missing
  firn::gl::PassTimer timer;
  try {
    scan.runOnce(buffers, timer);
    FAIL() << "expected std::logic_error";
  } catch (const std::logic_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("surface/scan_reduce.comp"), std::string::npos) << message;
    EXPECT_NE(message.find("storage binding " + std::to_string(FIRN_BINDING_SCAN_SUMS)), std::string::npos) << message;
  }
}

}  // namespace
