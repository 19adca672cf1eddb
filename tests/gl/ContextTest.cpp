// The context the GL tests run on is the driver they were asked to run on: ctest runs them a second time with
// GALLIUM_DRIVER=zink (tests/CMakeLists.txt), and a Mesa that quietly gave llvmpipe instead would test it twice.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "GlTest.h"

namespace {

TEST(Context, TheRendererIsTheDriverMesaWasAskedFor) {
  const firn::gl::ContextInfo& info = firn::test::glContext().info();
  const char* driver = std::getenv("GALLIUM_DRIVER");
  if (driver == nullptr || *driver == '\0') GTEST_SKIP() << "GALLIUM_DRIVER is not set: Mesa chooses, " << info.renderer;
  // A GPU's EGL device comes first (docs/platform.md, The headless context); Mesa's variables choose among its
  // software drivers on the surfaceless platform only.
  if (info.platform.rfind("EGL device", 0) == 0) GTEST_SKIP() << "Firn took " << info.platform << ", " << info.renderer;
  // Mesa's renderer strings begin with the Gallium driver's name: "zink (llvmpipe (LLVM 15.0.6, 256 bits))",
  // "llvmpipe (LLVM 15.0.6, 256 bits)".
  EXPECT_EQ(info.renderer.rfind(driver, 0), 0u) << "asked for " << driver << ", got " << info.renderer;
}

}  // namespace
