// What Firn requires of a driver, read from the contract, and the refusal of a driver with less (exit 4, naming the
// limit and the value found), with made-up limits: no GL context is needed.
#include <gtest/gtest.h>

#include <string>

#include "Error.h"
#include "gl/Limits.h"

namespace {

using firn::gl::DriverLimits;
using firn::gl::LimitRequirement;

TEST(DriverLimits, TheContractStatesEachRequirementWithItsGlLimit) {
  const auto& requirements = firn::gl::requiredLimits();
  const auto find = [&](const std::string& glLimit) -> const LimitRequirement* {
    for (const auto& requirement : requirements) {
      if (requirement.glLimit == glLimit) return &requirement;
    }
    return nullptr;
  };
  // docs/platform.md, Limits: the two that go beyond GL 4.3's minimums of 8 and 8.
  const LimitRequirement* bindings = find("GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS");
  ASSERT_NE(bindings, nullptr);
  EXPECT_EQ(bindings->name, "FIRN_REQUIRED_STORAGE_BINDINGS");
  EXPECT_EQ(bindings->required, 32);
  const LimitRequirement* computeBlocks = find("GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS");
  ASSERT_NE(computeBlocks, nullptr);
  EXPECT_EQ(computeBlocks->required, 16);
  for (const char* stated : {"GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS", "GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS",
                             "GL_MAX_COMPUTE_SHARED_MEMORY_SIZE", "GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS"}) {
    EXPECT_NE(find(stated), nullptr) << stated;
  }
}

TEST(DriverLimits, ARequirementWithoutItsGlLimitIsRefused) {
  EXPECT_THROW(firn::gl::parseRequiredLimits("#define FIRN_REQUIRED_THINGS 4  // how many things\n"), firn::GLError);
  EXPECT_THROW(firn::gl::parseRequiredLimits("#define FIRN_REQUIRED_THINGS  // GL_MAX_COMPUTE_SHARED_MEMORY_SIZE\n"),
               firn::GLError);
  const auto parsed = firn::gl::parseRequiredLimits(
      "#define FIRN_OTHER 3\n#define FIRN_REQUIRED_SHARED 512  // GL_MAX_COMPUTE_SHARED_MEMORY_SIZE (words)\n");
  ASSERT_EQ(parsed.size(), 1u);
  EXPECT_EQ(parsed[0].name, "FIRN_REQUIRED_SHARED");
  EXPECT_EQ(parsed[0].glLimit, "GL_MAX_COMPUTE_SHARED_MEMORY_SIZE");
  EXPECT_EQ(parsed[0].required, 512);
}

TEST(DriverLimits, ADriverWithLessIsExit4NamingTheLimitAndTheValueFound) {
  const auto& requirements = firn::gl::requiredLimits();
  DriverLimits enough;
  for (const auto& requirement : requirements) enough[requirement.glLimit] = requirement.required;
  EXPECT_NO_THROW(firn::gl::checkLimits(requirements, enough, "a driver at the requirements"));

  // GL 4.3's minimum of 8 storage blocks per compute shader: a conforming driver, short of Firn's 16.
  DriverLimits fewBlocks = enough;
  fewBlocks["GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS"] = 8;
  try {
    firn::gl::checkLimits(requirements, fewBlocks, "TestRenderer 1.0");
    FAIL() << "expected NoOpenGLError";
  } catch (const firn::NoOpenGLError& error) {
    EXPECT_EQ(error.code(), firn::ExitCode::NoOpenGL);
    EXPECT_EQ(static_cast<int>(error.code()), 4);
    const std::string message = error.what();
    EXPECT_NE(message.find("GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS = 8"), std::string::npos) << message;
    EXPECT_NE(message.find("at least 16"), std::string::npos) << message;
    EXPECT_NE(message.find("TestRenderer 1.0"), std::string::npos) << message;
    EXPECT_EQ(message.find("GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS"), std::string::npos) << message;
  }
  // Each shortfall is named, not only the first; a limit the driver did not report counts as 0.
  DriverLimits twoShort = enough;
  twoShort["GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS"] = 31;
  twoShort.erase("GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS");
  try {
    firn::gl::checkLimits(requirements, twoShort, "TestRenderer 1.0");
    FAIL() << "expected NoOpenGLError";
  } catch (const firn::NoOpenGLError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS = 31, Firn needs at least 32"), std::string::npos)
        << message;
    EXPECT_NE(message.find("GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS = 0"), std::string::npos) << message;
  }
}

}  // namespace
