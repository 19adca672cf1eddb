// Pictures from the command line (docs/command-line.md: `firn run … --png`,
// `firn view [--frames N --screenshot FILE]`): offscreen frames, the video, and the window under a virtual X server
// (xvfb-run), as a user runs them.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <stb_image.h>  // implemented once for this test binary, in RenderTest.cpp

#include "Cli.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::kOnXvfb;
using firn::test::onPath;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;

struct Picture {
  int width = 0, height = 0;
  double snowFraction = 0;  // share of near-white pixels: lit snow (the renderer's snow is white with a blue tint)
  int snowMinX = 1 << 30, snowMaxX = -1, snowMinY = 1 << 30, snowMaxY = -1;
};

// Near-white: every channel at least 215 of 255 and no more than 40 apart. The sky, the ground's lighter
// checks and the walls stay below 215 in some channel; lit snow is brighter (renderer tests pin the colours).
Picture readPicture(const fs::path& path) {
  Picture picture;
  int channels = 0;
  stbi_uc* pixels = stbi_load(path.c_str(), &picture.width, &picture.height, &channels, 3);
  if (pixels == nullptr) return picture;
  long snow = 0;
  for (int y = 0; y < picture.height; ++y) {
    for (int x = 0; x < picture.width; ++x) {
      const stbi_uc* p = pixels + 3 * (y * picture.width + x);
      const int low = std::min({p[0], p[1], p[2]}), high = std::max({p[0], p[1], p[2]});
      if (low < 215 || high - low > 40) continue;
      ++snow;
      picture.snowMinX = std::min(picture.snowMinX, x);
      picture.snowMaxX = std::max(picture.snowMaxX, x);
      picture.snowMinY = std::min(picture.snowMinY, y);
      picture.snowMaxY = std::max(picture.snowMaxY, y);
    }
  }
  stbi_image_free(pixels);
  picture.snowFraction = double(snow) / (double(picture.width) * picture.height);
  return picture;
}

// A 0.4 m ball of snow in the middle of a 1.2 m domain, seen from the front by the scene's camera: its
// silhouette is a disc of angular radius asin(0.2 / 1.2) about the image centre, 0.2/1.2 / tan(20°) = 46% of the
// half-height, so about π·0.46²·(3/4)·(1/4)·… ≈ 12% of a 4:3 image.
const char* const kBallScene = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 2 },
  "gravity": [0, 0, 0],
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.2, "material": "snow" } ],
  "camera": { "position": [0.6, 0.6, 1.8], "target": [0.6, 0.6, 0.6], "fov_deg": 40 } })";

// The disc's area: radius tan(asin(1/6)) / tan(20°) · 60 px = 27.6 px about the image centre (79.5, 59.5), so
// π 27.6² / (160 · 120) = 12.5% of the picture, and its box spans 51.9–107.1 by 31.9–87.1 px.
constexpr double kBallRadiusPx = 27.6;

// By default the pictures show the snow's surface, lit from above: its upper part reads near-white (measured: 7.1%
// of the picture, the upper two thirds of the disc) and every near-white pixel lies within the ball's projected box
// (give or take a pixel: the surface stands a tenth of a particle spacing proud of the particles, 0.2 px here).
TEST(Pictures, RunPngDrawsTheSurfaceByDefaultWhereTheSnowIs) {
  const fs::path folder = freshDirectory("png_surface");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const Result result =
      runFirn("run " + scene.string() + " --png --no-ply --width 160 --height 120 --out " + (folder / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_NE(result.output.find("firn: surface: nodes"), std::string::npos) << result.output;
  for (int frame = 0; frame <= 2; ++frame) {
    const Picture picture = readPicture(folder / "out" / ("frame_000" + std::to_string(frame) + ".png"));
    ASSERT_EQ(picture.width, 160);
    // At least the lit upper half of the disc (6.2%); no more than the disc.
    EXPECT_GT(picture.snowFraction, 0.06) << "frame " << frame;
    EXPECT_LT(picture.snowFraction, 0.125) << "frame " << frame;
    EXPECT_GE(picture.snowMinX, 79.5 - kBallRadiusPx - 1) << "frame " << frame;
    EXPECT_LE(picture.snowMaxX, 79.5 + kBallRadiusPx + 1) << "frame " << frame;
    EXPECT_GE(picture.snowMinY, 59.5 - kBallRadiusPx - 1) << "frame " << frame;
    EXPECT_LE(picture.snowMaxY, 59.5 + kBallRadiusPx + 1) << "frame " << frame;
  }
}

TEST(Pictures, RunPngRendersEachFrameWhereTheSnowIs) {
  const fs::path folder = freshDirectory("png");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const Result result = runFirn("run " + scene.string() + " --png --render particles --width 160 --height 120 --out " +
                                (folder / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  for (int frame = 0; frame <= 2; ++frame) {
    const Picture picture = readPicture(folder / "out" / ("frame_000" + std::to_string(frame) + ".png"));
    ASSERT_EQ(picture.width, 160);
    ASSERT_EQ(picture.height, 120);
    // The disc's area is 12.5% (kBallRadiusPx). Shading darkens the rim below the near-white threshold, so at least
    // half of that must read as snow, and no more than the disc plus a pixel of sprite overhang all round.
    EXPECT_GT(picture.snowFraction, 0.06) << "frame " << frame;
    EXPECT_LT(picture.snowFraction, 0.14) << "frame " << frame;
    // Centred: the snow's box straddles the image centre within 3 pixels (jitter, one sprite radius).
    EXPECT_NEAR(0.5 * (picture.snowMinX + picture.snowMaxX), 79.5, 3.0) << "frame " << frame;
    EXPECT_NEAR(0.5 * (picture.snowMinY + picture.snowMaxY), 59.5, 3.0) << "frame " << frame;
  }
}

// A ball of 0.15 m resting over a floor at one end of a 1.6 × 0.8 × 1.2 m domain, and no camera section.
const char* const kOffCentreScene = R"({
  "grid": { "cells": [64, 32, 48], "cell_size": 0.025 },
  "time": { "dt": 5e-4, "frame_rate": 50, "frames": 2 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [1.2, 0.3, 0.6], "radius": 0.15, "material": "snow" } ],
  "colliders": [ { "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "friction": 0.5 } ] })";

// Without a camera section the camera frames the snow and the floor under it, not the domain: measured at 160×120,
// the ball's near-white box covered 1.4% of the picture (centred 24 px right of the image's centre) when the camera
// framed the whole floor plane across the domain, and covers 20.0% framing the snow (centred within 1 px). Half of
// the latter, 10%, separates the two by far; the centre may stray by a sprite's few pixels.
TEST(Pictures, DefaultCameraFramesTheSnowNotTheDomain) {
  const fs::path folder = freshDirectory("png_framing");
  const fs::path scene = writeScene(folder, "offcentre.json", kOffCentreScene);
  const Result result = runFirn("run " + scene.string() + " --frames 0 --no-ply --png --width 160 --height 120 --out " +
                                (folder / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const Picture picture = readPicture(folder / "out" / "frame_0000.png");
  ASSERT_GE(picture.snowMaxX, 0) << "no snow in the picture";
  const double boxShare = double(picture.snowMaxX - picture.snowMinX + 1) * (picture.snowMaxY - picture.snowMinY + 1) /
                          (double(picture.width) * picture.height);
  EXPECT_GT(boxShare, 0.10);
  EXPECT_NEAR(0.5 * (picture.snowMinX + picture.snowMaxX), 79.5, 4.0);
}

// The domain's box is outlined only with --domain-box (the renderer's own test places its lines): the two pictures
// differ, and only the outlined one has the box's lines.
TEST(Pictures, DomainBoxOnlyOnRequest) {
  const fs::path folder = freshDirectory("png_domain_box");
  const fs::path scene = writeScene(folder, "offcentre.json", kOffCentreScene);
  const auto picture = [&](const std::string& extra, const std::string& out) {
    const Result result = runFirn("run " + scene.string() + " --frames 0 --no-ply --png --render particles --width 160 "
                                  "--height 120 " + extra + " --out " + (folder / out).string());
    EXPECT_EQ(result.exitCode, 0) << result.output;
    std::ifstream in(folder / out / "frame_0000.png", std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string plain = picture("", "plain");
  const std::string outlined = picture("--domain-box", "outlined");
  ASSERT_FALSE(plain.empty());
  EXPECT_NE(plain, outlined);
}

// A scene whose surface settings do not suit its particles (a kernel 24 reconstruction cells wide, twice the most)
// is drawn as particles when --render is left out, with a note saying why; asked for, the surface stays exit 2
// (SurfaceCli.BadSettingsExitTwoNamingTheKey).
TEST(Pictures, UnsuitedSurfaceSettingsFallBackToParticlesByDefault) {
  const fs::path folder = freshDirectory("png_fallback");
  const std::string ball = kBallScene;
  const std::string wideKernel = R"(, "surface": { "resolution": 8, "smoothing": 6 } })";
  const fs::path scene = writeScene(folder, "wide_kernel.json", ball.substr(0, ball.rfind('}')) + wideKernel);
  const Result result = runFirn("run " + scene.string() + " --frames 0 --no-ply --png --width 160 --height 120 --out " +
                                (folder / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_NE(result.output.find("firn: note: drawing the snow as particles"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("surface.resolution"), std::string::npos) << result.output;
  const Picture picture = readPicture(folder / "out" / "frame_0000.png");
  EXPECT_GT(picture.snowFraction, 0.06) << "the particles, as RunPngRendersEachFrameWhereTheSnowIs measures them";
}

TEST(Pictures, Mp4AssemblesTheFramesWhenFfmpegIsInstalled) {
  if (!onPath("ffmpeg")) GTEST_SKIP() << "ffmpeg is not installed (scripts/setup.sh installs it)";
  const fs::path folder = freshDirectory("mp4");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const fs::path video = folder / "ball.mp4";
  const Result result = runFirn("run " + scene.string() + " --mp4 " + video.string() +
                                " --width 160 --height 120 --no-ply --out " + (folder / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  // An MP4 file starts with its "ftyp" box: 4 bytes of size, then the type.
  std::ifstream in(video, std::ios::binary);
  char header[8] = {};
  in.read(header, sizeof header);
  EXPECT_EQ(std::string(header + 4, 4), "ftyp");
  EXPECT_TRUE(fs::exists(folder / "out" / "frame_0002.png"));
}

TEST(Pictures, Mp4WithoutFfmpegSaysSoBeforeRunning) {
  const fs::path folder = freshDirectory("mp4_missing");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const Result result = runFirn("run " + scene.string() + " --mp4 " + (folder / "ball.mp4").string() + " --out " +
                                    (folder / "out").string(),
                                "PATH=/nonexistent");
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("ffmpeg"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(folder / "out" / "stats.csv")) << "nothing is simulated before the problem is reported";
}

// docs/platform.md, The viewer under Xvfb: `xvfb-run -a -s "-screen 0 1280x720x24" firn view …` is how the viewer is
// tested (through tests/support/on-xvfb.sh, which keeps firn's exit status).
TEST(Viewer, RunsUnderXvfbAndWritesANonBlankScreenshot) {
  if (!onPath("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs the xvfb package)";
  const fs::path folder = freshDirectory("view");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const fs::path screenshot = folder / "view.png";
  for (const std::string render : {"--render particles", "" /* the surface */}) {
    SCOPED_TRACE(render);
    const Result result = runFirn("view " + scene.string() + " " + render +
                                      " --frames 10 --width 320 --height 240 --screenshot " + screenshot.string(),
                                  kOnXvfb);
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_NE(result.output.find("10 frames"), std::string::npos) << result.output;
    const Picture picture = readPicture(screenshot);
    ASSERT_EQ(picture.width, 320);
    ASSERT_EQ(picture.height, 240);
    // The viewer starts from the scene's camera, so the ball fills the same share as offscreen (see above), as
    // particles or as its surface (the default, which the V key switches from).
    EXPECT_GT(picture.snowFraction, 0.06);
    EXPECT_LT(picture.snowFraction, 0.14);
  }
}

// A scripted snowball (--throw-at, as the T key): the particle count grows by one snowball.
TEST(Viewer, ThrownSnowballAddsItsParticles) {
  if (!onPath("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs the xvfb package)";
  const fs::path folder = freshDirectory("view_throw");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const auto finalParticles = [&](const std::string& extra) {
    const Result result = runFirn("view " + scene.string() + " --frames 4 --width 160 --height 120 " + extra,
                                  kOnXvfb);
    EXPECT_EQ(result.exitCode, 0) << result.output;
    const std::size_t end = result.output.rfind(" particles");
    const std::size_t start = result.output.rfind(' ', end - 1);
    return std::stol(result.output.substr(start + 1, end - start - 1));
  };
  const long withoutThrow = finalParticles("");
  const long withThrow = finalParticles("--throw-at 2");
  // A sphere of 4 cells' radius at 8 particles per cell holds about 8 · 4π/3 · 4³ = 2,145 particles.
  EXPECT_NEAR(double(withThrow - withoutThrow), 2145.0, 0.05 * 2145.0);
}

TEST(Viewer, WithoutADisplayExitsFourAndSaysWhatToDo) {
  const Result result = runFirn("view --frames 1", "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(result.exitCode, 4) << result.output;
  EXPECT_NE(result.output.find("xvfb-run"), std::string::npos) << result.output;
}

TEST(Viewer, ScreenshotNeedsFrames) {
  const Result result = runFirn("view --screenshot x.png");
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("--frames"), std::string::npos) << result.output;
}

}  // namespace
