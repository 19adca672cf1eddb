#pragma once
// `firn view`: the interactive window (GLFW, OpenGL 4.3 core). Physics runs in fixed steps of the scene's dt
// through a StepAccumulator, apart from drawing; the renderer draws the particles straight from the GPU.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "render/Renderer.h"
#include "scene/Scene.h"

namespace firn {

struct ViewOptions {
  std::optional<int> frames;           // exit after this many drawn frames (scripted runs)
  std::filesystem::path screenshotPath;  // with `frames`: the last frame, as PNG
  int widthPx = 1280;
  int heightPx = 720;
  render::ColorMode colorMode = render::ColorMode::Material;
  // Particles or the surface (V switches); unset, the surface where the scene's settings allow it
  // (SimulationSession::pictureRenderMode).
  std::optional<render::RenderMode> renderMode;
  bool domainBox = false;              // outline the domain's box (B switches)
  std::vector<int> throwAtFrames;      // scripted snowballs: thrown from the camera at these frames (as key T)
  bool showProgress = false;           // progress on stderr while sampling (in place on a terminal)
  std::string transferShapes;          // the transfer shapes to time (SimulationOptions); empty: every shape
  // The scene editor (apps/firn/SceneEditor.h): the window opens editing `scenePath`, the scene paused at its start.
  bool edit = false;
  std::filesystem::path scenePath;
  std::filesystem::path replayPath;    // with `edit`: the input replayed from this file (apps/firn/EditorInput.h)
  std::filesystem::path recordPath;    // with `edit`: the input recorded into this file at the end
};

// Runs until the window closes (or `frames` frames). Throws NoOpenGLError (exit 4) without a display or a
// GL 4.3 core context, InputError for a bad scene (or replayed input that does not fit the editor), SimulationError
// (exit 3) when a scripted run goes unstable.
void runViewer(const Scene& scene, const ViewOptions& options);

}  // namespace firn
