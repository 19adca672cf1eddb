// The `firn` command line (design.md, "The command line"). Exit status: 0 success, 2 bad input,
// 3 unstable or overflowed simulation, 4 no usable OpenGL 4.3.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "Error.h"
#include "gl/Context.h"
#include "run/HeadlessRun.h"
#include "scene/Scene.h"

namespace {

int runCommand(const std::string& scenePath, std::optional<int> frames, const std::string& outputDir, bool noPly,
               bool passTimes) {
  const firn::Scene scene = scenePath.empty() ? firn::defaultScene() : firn::loadScene(scenePath);
  firn::RunOptions options;
  options.frames = frames;
  options.outputDir = outputDir;
  options.writePly = !noPly;
  options.showProgress = isatty(STDERR_FILENO) != 0;
  options.passTimes = passTimes;
  const firn::RunSummary summary = firn::runHeadless(scene, options, std::cerr);
  std::printf("firn: wrote %d frames (%zu particles, %llu steps) to %s in %.1f s: %.2f ms per step on %s\n",
              summary.frames + 1, summary.particles, static_cast<unsigned long long>(summary.steps),
              outputDir.c_str(), summary.wallS,
              summary.steps > 0 ? 1e3 * summary.simulationWallS / double(summary.steps) : 0.0, summary.renderer.c_str());
  return 0;
}

int infoCommand() {
  firn::gl::HeadlessContext context;
  const firn::gl::ContextInfo& info = context.info();
  std::printf("platform  %s\nvendor    %s\nrenderer  %s\nversion   %s\nfloat atomics (GL_NV_shader_atomic_float)  %s\n"
              "max shader storage block  %lld MiB\n",
              info.platform.c_str(), info.vendor.c_str(), info.renderer.c_str(), info.version.c_str(),
              info.hasFloatAtomics ? "yes" : "no", info.maxStorageBlockBytes / (1024 * 1024));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Firn: a GPU snow engine (Material Point Method, Stomakhin et al. 2013) on OpenGL 4.3 compute shaders"};
  app.require_subcommand(1);

  std::string scenePath;
  std::optional<int> frames;
  std::string outputDir = "firn-out";
  bool noPly = false;
  bool passTimes = false;
  CLI::App* run = app.add_subcommand("run", "Simulate a scene headless (EGL) and write stats.csv and PLY frames");
  run->add_option("scene", scenePath, "Scene file (JSON); without it, the built-in snowball-at-a-wall scene")
      ->check(CLI::ExistingFile);
  run->add_option("--frames", frames, "Number of frames after frame 0 (default: the scene's time.frames)")
      ->check(CLI::Range(0, 1000000));
  run->add_option("--out", outputDir, "Output folder for stats.csv and frame_NNNN.ply")->capture_default_str();
  run->add_flag("--no-ply", noPly, "Write stats.csv only, no point caches");
  run->add_flag("--pass-times", passTimes, "Time each GPU pass (GL_TIME_ELAPSED) and print the means; slows the run");

  app.add_subcommand("info", "Show the OpenGL context Firn gets (set FIRN_EGL_DEVICE=N to pick an EGL device)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int status = app.exit(error);
    return status == 0 ? 0 : static_cast<int>(firn::ExitCode::BadInput);
  }

  try {
    if (run->parsed()) return runCommand(scenePath, frames, outputDir, noPly, passTimes);
    return infoCommand();
  } catch (const firn::Error& error) {
    std::fprintf(stderr, "\nfirn: error: %s\n", error.what());
    return static_cast<int>(error.code());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "\nfirn: internal error: %s\n", error.what());
    return 1;
  }
}
