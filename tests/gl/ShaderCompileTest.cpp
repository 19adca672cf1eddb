// Shader failures are loud and precise: the driver's log with file:line of the original source.
#include <gtest/gtest.h>

#include <string>

#include "Error.h"
#include "GlTest.h"
#include "gl/Program.h"
#include "sim/GpuLayout.h"

namespace {

TEST(ShaderCompile, ErrorNamesIncludedFileAndLine) {
  firn::test::glContext();
  firn::gl::ShaderLibrary library({
      {"test/main.comp", "#version 430 core\nlayout(local_size_x = 1) in;\n#include \"test/helper.glsl\"\n"
                         "void main() { helper(); }\n"},
      {"test/helper.glsl", "// a helper with a typo on line 3\nvoid helper() {\n  undeclaredVariable = 1.0;\n}\n"},
  });
  try {
    firn::gl::Program::compute(library, "test/main.comp", {});
    FAIL() << "expected GLError";
  } catch (const firn::GLError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("compiling test/main.comp failed"), std::string::npos) << message;
    EXPECT_NE(message.find("test/helper.glsl:3"), std::string::npos) << message;
    EXPECT_NE(message.find("undeclaredVariable"), std::string::npos) << message;
  }
}

TEST(ShaderCompile, EveryPassCompilesForEveryConfiguration) {
  firn::test::glContext();
  const firn::gl::ShaderLibrary library;
  for (const char* kernel : {"FIRN_KERNEL_QUADRATIC", "FIRN_KERNEL_CUBIC"}) {
    for (const char* transfer : {"FIRN_TRANSFER_APIC", "FIRN_TRANSFER_PIC_FLIP"}) {
      firn::gl::ShaderOptions options;
      options.defines = {{kernel, "1"}, {transfer, "1"}, {"FIRN_HAS_COLLIDERS", "1"},
                         {"FIRN_PARTICLE_GROUP_SIZE", "64"}, {"FIRN_WALL_CELLS", "2"}};
      for (const auto& binding : firn::gpu::bindingDefines()) options.defines.push_back(binding);
      for (const char* pass : {"sim/prepare_grid.comp", "sim/clear_grid.comp", "sim/p2g.comp", "sim/update_grid.comp",
                               "sim/g2p.comp", "sim/compute_volumes.comp"}) {
        EXPECT_NO_THROW(firn::gl::Program::compute(library, pass, options)) << pass << " " << kernel << " " << transfer;
      }
    }
  }
}

}  // namespace
