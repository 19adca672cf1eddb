#pragma once
// `firn run`: a scene simulated headless, writing stats.csv, run.json, PLY frames, bodies.csv where objects move and,
// if asked, pictures, the snow's surface and the moving objects as meshes, VDB caches and the energy budget's plot.
#include <filesystem>
#include <iosfwd>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "render/Renderer.h"
#include "scene/Scene.h"

namespace firn {

class DomainShare;

struct RunOptions {
  std::optional<int> frames;       // overrides the scene's time.frames
  std::filesystem::path outputDir = "firn-out";
  bool writePly = true;
  bool showProgress = false;       // progress on stderr: in place on a terminal, a line every few seconds elsewhere
  bool passTimes = false;          // time every pass on the GPU and print a table at the end
  bool writePng = false;           // render each frame offscreen to frame_NNNN.png
  glm::ivec2 imageSizePx{1280, 720};
  render::ColorMode colorMode = render::ColorMode::Material;
  // The pictures' snow: particles or its surface; unset, the surface where the scene's settings allow it
  // (SimulationSession::pictureRenderMode).
  std::optional<render::RenderMode> renderMode;
  bool domainBox = false;          // outline the domain's box in the pictures
  bool writeMesh = false;          // the snow's surface as frame_NNNN_surface.ply, each moving object as <object>_NNNN.ply
  bool writeVdb = false;           // the snow as frame_NNNN.vdb: density and a level set of its surface
  std::filesystem::path videoPath; // non-empty: assemble the PNG frames into this video with ffmpeg
  int checkpointEvery = 0;         // > 0: write checkpoint_NNNN.firn every this many frames
  std::filesystem::path resumePath;  // non-empty: continue from this checkpoint (of the same scene)
  int gpuOrdinal = 0;              // without FIRN_EGL_DEVICE, which of the machine's GPUs (gl::HeadlessContext)
  std::string transferShapes;      // the transfer shapes to time (SimulationOptions); empty: every shape
  bool writePlot = false;          // energy.png, the energy budget over time, when the run ends (io/EnergyPlot.h)
  std::vector<std::string> commandLine;  // as run.json records it

  bool writesPictures() const { return writePng || !videoPath.empty(); }
  bool writesSurfaceCaches() const { return writeMesh || writeVdb; }
};

struct RunSummary {
  int firstFrame = 0;              // 0, or the checkpoint's frame for a resumed run
  int frames = 0;                  // the last frame written
  std::uint64_t steps = 0;
  std::size_t particles = 0;
  double wallS = 0;                // whole run, start-up included
  double simulationWallS = 0;      // stepping only, frame output excluded
  std::string renderer;
};

// Frame N is the state at N / frame_rate; frame 0 is the initial state. A resumed run writes stats.csv, bodies.csv
// and the frames from the checkpoint's frame on. Throws InputError (bad scene or output), SimulationError (unstable:
// the frames written so far stay on disk) or NoOpenGLError; run.json, written as the run starts, then says how it
// ended, and with `writePlot` energy.png shows the budget up to there.
// With a `share` this process simulates its part of the domain (sim/DomainShare.h) and every share calls it alike;
// the share that writes the output writes the files a single process would, byte for byte.
RunSummary runHeadless(const Scene& scene, const RunOptions& options, std::ostream& log, DomainShare* share = nullptr);

// `firn run --check`: what runHeadless does before its first step, and nothing after — the checkpoint read and
// resumed, the particle budget, sampling, the distance fields' bake, pre-flight, the simulation's GPU buffers and
// programs and, for pictures or surface caches, their renderer and the surface's settings — with pre-flight's
// report on `log` as a run gives it. Simulates nothing and writes no file; the output folder is not looked at.
// Returns the line that says the scene is ready (the particles, frames and steps; empty on a share that does not
// write). Throws as runHeadless would before its first step: InputError (exit 2), NoOpenGLError (exit 4).
std::string checkHeadless(const Scene& scene, const RunOptions& options, std::ostream& log,
                          DomainShare* share = nullptr);

}  // namespace firn
