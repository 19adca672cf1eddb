// What a scene file may ask for, at the edges users reach with hostile input (docs/scene-format.md): Lamé scales
// that leave no stress, steps a float cannot hold or a frame cannot fit, and domains so far from the origin that
// float positions lose the cell. Each is bad input naming the key and why.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "Error.h"
#include "scene/Scene.h"

namespace firn {
namespace {

std::string sceneText(const std::string& grid, const std::string& time, const std::string& bodyKeys) {
  return R"({ "grid": { "cells": [24, 24, 24], "cell_size": 0.05 )" + grid + R"( },
    "time": { )" + time + R"( },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.15, "material": "snow" )" + bodyKeys +
         " } ] }";
}

// The message of the InputError that parsing `text` throws, or "" if it parses.
std::string refusal(const std::string& text) {
  try {
    parseScene(text, "limits.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

const char* const kTime = R"("dt": 1e-3, "frame_rate": 50)";

TEST(SceneValidation, LameScalesMayNotBothBeZero) {
  const std::string message = refusal(sceneText("", kTime, R"(, "lambda_scale": 0, "mu_scale": 0)"));
  EXPECT_EQ(message.rfind("limits.json: bodies[0].mu_scale: must not be 0 together with lambda_scale: with both 0 the "
                          "body has no elastic stress",
                          0),
            0u)
      << message;
  // Either alone is a material: λ = 0 keeps μ's resistance, μ = 0 is a compressible fluid.
  EXPECT_EQ(refusal(sceneText("", kTime, R"(, "lambda_scale": 0)")), "");
  EXPECT_EQ(refusal(sceneText("", kTime, R"(, "mu_scale": 0)")), "");
}

// 1e-300 s is 0 as a float, the GPU's type for the step.
TEST(SceneValidation, StepBelowAFloatIsRefused) {
  const std::string message = refusal(sceneText("", R"("dt": 1e-300, "frame_rate": 50)", ""));
  EXPECT_EQ(message, "limits.json: time.dt: must be a normal 32-bit float, between 1.17549e-38 and 3.40282e+38 s, as "
                     "the GPU takes it (got 1e-300)");
}

// A frame of 1e300 s at dt = 1e-3 s is 1e303 steps; a frame of 1/30 s at 1e-9 s is 3.3e7: both beyond the 1e6 a
// frame may take, the first naming frame_rate (below 1 Hz), the second dt. Half a million steps is allowed.
TEST(SceneValidation, FrameOfMoreThanAMillionStepsIsRefused) {
  EXPECT_EQ(refusal(sceneText("", R"("dt": 1e-3, "frame_rate": 1e-300)", "")).rfind(
                "limits.json: time.frame_rate: a frame (1 / frame_rate = 1e+300 s) would take 1e+303 steps of dt = "
                "0.001 s, more than the 1,000,000 steps a frame may take",
                0),
            0u);
  EXPECT_EQ(refusal(sceneText("", R"("dt": 1e-9, "frame_rate": 30)", "")).rfind(
                "limits.json: time.dt: a frame (1 / frame_rate = 0.0333333 s) would take 3.33e+07 steps", 0),
            0u);
  EXPECT_EQ(refusal(sceneText("", R"("dt": 4e-8, "frame_rate": 50)", "")), "");
}

// At 1e5 m floats are 2⁻⁷ m = 7.8 mm apart, 0.156 of a 0.05 m cell: refused (over a hundredth). At 1e7 m, 1 m.
TEST(SceneValidation, GridFarFromTheOriginIsRefusedWithItsPositionResolution) {
  GridSpec grid;
  grid.cellSizeM = 0.05;
  grid.cells = glm::ivec3(24);
  grid.originM = {1e5, 0, 0};
  EXPECT_DOUBLE_EQ(grid.positionResolutionM(), std::ldexp(1.0, -7));
  const std::string message = refusal(sceneText(R"(, "origin": [1e5, 0, 0])", kTime, ""));
  EXPECT_NE(message.find("limits.json: grid.origin: positions out to the domain's far corner (100001, 1.2, 1.2) m are "
                         "32-bit floats on the GPU, 0.00781 m apart there: 0.156 of a cell"),
            std::string::npos)
      << message;
  EXPECT_NE(refusal(sceneText(R"(, "origin": [1e7, 0, 0])", kTime, "")).find("1 m apart there: 20 of a cell"),
            std::string::npos);
  // Beyond a float's range the resolution is infinite, not NaN, and still refused.
  grid.originM = {1e300, 0, 0};
  EXPECT_TRUE(std::isinf(grid.positionResolutionM()));
}

}  // namespace
}  // namespace firn
