#include "Viewer.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gl/GL.h"  // GLEW's header must come before GLFW's
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "EditorInput.h"
#include "Error.h"
#include "SceneEditor.h"
#include "gl/Context.h"
#include "io/Text.h"
#include "run/SimulationSession.h"
#include "scene/JsonChecker.h"
#include "run/StepAccumulator.h"
#include "scene/Sampling.h"
#include "sim/Simulation.h"
#include "surface/SurfaceReconstruction.h"

namespace firn {
namespace {

using Clock = std::chrono::steady_clock;

// Physics may use up to this much wall time per drawn frame, so the window stays responsive (about 30 frames
// per second at most spent stepping) on a machine that cannot keep real time.
constexpr double kPhysicsBudgetPerFrameS = 1.0 / 30.0;
constexpr double kTitleIntervalS = 0.25;
constexpr double kMinSpeed = 1.0 / 64, kMaxSpeed = 4.0;
// Snowballs thrown from the camera: radius in cells (big enough to hold together, small beside a scene),
// speed (m/s), and how many the particle buffers keep room for.
constexpr double kSnowballRadiusCells = 4.0;
constexpr double kSnowballSpeedMPerS = 8.0;
constexpr int kSnowballCapacity = 8;
// Rigid balls thrown from the camera (key O) as snowballs are: the same size and speed; ice's density, so that a ball
// ploughs into snow several times lighter; and how many spare balls wait parked in the simulation's table of bodies.
constexpr double kRigidBallDensityKgPerM3 = 917;
constexpr std::size_t kRigidBallCapacity = 4;

// The snowball T throws: a sphere of the first body's material and particles per cell, at the domain's centre.
// A points body's particles per cell, (cell_size / the cloud's spacing)³, can be any number: the snowball takes
// at most what a sampled body may (docs/scene-format.md, bodies).
Body snowballBody(const Scene& scene) {
  constexpr double maxSampledParticlesPerCell = 1000;
  Body body;
  body.shape = BodyShape::Sphere;
  body.radiusM = kSnowballRadiusCells * scene.grid.cellSizeM;
  body.centerM = scene.grid.originM + 0.5 * glm::dvec3(scene.grid.cells) * scene.grid.cellSizeM;
  body.materialIndex = scene.bodies.front().materialIndex;
  body.particlesPerCell = std::min(scene.bodies.front().particlesPerCell, maxSampledParticlesPerCell);
  return body;
}

// A spare rigid ball, parked at the domain's centre until thrown (RigidBody::parked, Simulation::launchRigidBody): a
// uniform sphere of the snowball's radius.
RigidBody spareBall(const Scene& scene) {
  RigidBody ball;
  ball.shape = RigidShape::Sphere;
  ball.radiusM = kSnowballRadiusCells * scene.grid.cellSizeM;
  ball.centerM = scene.grid.originM + 0.5 * glm::dvec3(scene.grid.cells) * scene.grid.cellSizeM;
  setUniformDensity(ball, shapeMassProperties(ball), kRigidBallDensityKgPerM3);
  ball.parked = true;
  return ball;
}

// The scene the viewer simulates: the file's, with the spare balls after its own rigid bodies.
Scene withSpareBalls(Scene scene) {
  scene.rigidBodies.insert(scene.rigidBodies.end(), kRigidBallCapacity, spareBall(scene));
  return scene;
}

std::string& lastGlfwError() {
  static std::string message = "no error reported";
  return message;
}

void rememberGlfwError(int code, const char* description) {
  char text[32];
  std::snprintf(text, sizeof text, " (GLFW error 0x%05X)", code);
  lastGlfwError() = std::string(description) + text;
}

// glfwInit/glfwTerminate as an object, so every way out of runViewer terminates GLFW.
class GlfwSession {
 public:
  GlfwSession() {
    glfwSetErrorCallback(rememberGlfwError);
    if (glfwInit() != GLFW_TRUE) {
      throw NoOpenGLError("firn view needs a window system, and GLFW could not start one: " + lastGlfwError() +
                          ". Without a display, run `xvfb-run -a firn view …`, or use `firn run --png` for pictures");
    }
  }
  ~GlfwSession() { glfwTerminate(); }
  GlfwSession(const GlfwSession&) = delete;
  GlfwSession& operator=(const GlfwSession&) = delete;
};

struct WindowDeleter {
  void operator()(GLFWwindow* window) const { glfwDestroyWindow(window); }
};
using WindowPtr = std::unique_ptr<GLFWwindow, WindowDeleter>;

// A camera that turns about a target point: yaw about +y, pitch up to just short of the poles.
class OrbitCamera {
 public:
  OrbitCamera(const render::Camera& start, const Scene& scene)
      : scene_(&scene), targetM_(start.targetM), fovDeg_(start.fovDeg) {
    const glm::vec3 offset = start.positionM - start.targetM;
    distanceM_ = glm::length(offset);
    yawRad_ = std::atan2(offset.x, offset.z);
    pitchRad_ = std::asin(glm::clamp(offset.y / distanceM_, -1.0f, 1.0f));
  }

  render::Camera camera() const {
    render::Camera camera;
    camera.targetM = targetM_;
    camera.positionM = targetM_ + distanceM_ * direction();
    camera.fovDeg = fovDeg_;
    render::fitDepthRange(camera, *scene_);
    return camera;
  }

  void orbit(double dxPx, double dyPx) {
    constexpr double radiansPerPx = 0.005;
    constexpr float maxPitchRad = 1.55f;  // about 89°: the view direction never lines up with +y
    yawRad_ -= float(dxPx * radiansPerPx);
    pitchRad_ = glm::clamp(pitchRad_ + float(dyPx * radiansPerPx), -maxPitchRad, maxPitchRad);
  }

  // Moves the target in the view plane so that the point under the cursor follows it.
  void pan(double dxPx, double dyPx, int viewportHeightPx) {
    const float metresPerPx =
        2.0f * distanceM_ * std::tan(glm::radians(fovDeg_) / 2) / float(std::max(viewportHeightPx, 1));
    const glm::vec3 forward = -direction();
    const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 1, 0)));
    const glm::vec3 up = glm::cross(right, forward);
    targetM_ += metresPerPx * (-float(dxPx) * right + float(dyPx) * up);
  }

  void zoom(double wheelSteps) { distanceM_ *= float(std::pow(0.9, wheelSteps)); }

  // The same view of another scene (the editor's next simulation).
  OrbitCamera of(const Scene& scene) const {
    OrbitCamera camera = *this;
    camera.scene_ = &scene;
    return camera;
  }

 private:
  glm::vec3 direction() const {
    return {std::cos(pitchRad_) * std::sin(yawRad_), std::sin(pitchRad_), std::cos(pitchRad_) * std::cos(yawRad_)};
  }

  const Scene* scene_;  // a pointer, so that the camera can be reassigned (F reframes)
  glm::vec3 targetM_;
  float fovDeg_;
  float distanceM_ = 1;
  float yawRad_ = 0;
  float pitchRad_ = 0;
};

// Where along the ray origin + t·direction (t ≥ 0) it enters the box, by the slab method; nothing if it misses.
std::optional<float> rayEntersBox(const glm::vec3& origin, const glm::vec3& direction, const glm::vec3& boxMin,
                                  const glm::vec3& boxMax) {
  float enter = 0, leave = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(direction[axis]) < 1e-12f) {
      if (origin[axis] < boxMin[axis] || origin[axis] > boxMax[axis]) return std::nullopt;
      continue;
    }
    float near = (boxMin[axis] - origin[axis]) / direction[axis];
    float far = (boxMax[axis] - origin[axis]) / direction[axis];
    if (near > far) std::swap(near, far);
    enter = std::max(enter, near);
    leave = std::min(leave, far);
  }
  if (enter > leave) return std::nullopt;
  return enter;
}

// The panel's font: Debian's DejaVu Sans (fonts-dejavu-core) with the characters Firn's messages use — Greek,
// punctuation such as "–", super- and subscripts, arrows and mathematical operators ("√", "≤", "×"); ImGui's own font
// has Latin-1 alone and shows the rest as "?". Without the file, ImGui's own.
void useMessagesFont() {
  static const ImWchar ranges[] = {0x0020, 0x00FF, 0x0370, 0x03FF, 0x2000, 0x206F, 0x2070, 0x209F,
                                   0x2190, 0x21FF, 0x2200, 0x22FF, 0};
  const char* const path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  std::error_code error;
  if (std::filesystem::is_regular_file(path, error)) {
    ImGui::GetIO().Fonts->AddFontFromFileTTF(path, 15.0f, nullptr, ranges);
  }
}

// The editor's half of the window (--edit): Dear ImGui's context with its GLFW and OpenGL 3 backends, the scene
// editor, and its input replayed from a file or recorded into one. It lives as long as the window, across the
// simulations the editor runs.
// Dear ImGui's context, made first and destroyed last of the editor's half (the editor's panel draws into it).
class ImGuiContextHolder {
 public:
  ImGuiContextHolder() { ImGui::CreateContext(); }
  ~ImGuiContextHolder() { ImGui::DestroyContext(); }
  ImGuiContextHolder(const ImGuiContextHolder&) = delete;
  ImGuiContextHolder& operator=(const ImGuiContextHolder&) = delete;
};

// The document the editor opens: the scene file, or for a file that does not exist yet Firn's built-in scene, to be
// saved there (a scene begun in the window, without writing JSON first).
SceneDocument openOrBegin(const std::filesystem::path& path) {
  std::error_code error;
  if (std::filesystem::exists(path, error)) return SceneDocument::open(path);
  std::printf("firn view: %s does not exist yet: editing Firn's built-in scene, which Ctrl+S saves there\n",
              path.string().c_str());
  return SceneDocument::create(embeddedSceneFiles().at("snowball_wall.json"), path);
}

class EditorLayer {
 public:
  EditorLayer(GLFWwindow* window, const ViewOptions& options, const gl::ContextInfo& gl)
      : options_(options), editor_(openOrBegin(options.scenePath), gl) {
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the user's files
    useMessagesFont();
    // The window's callbacks are the viewer's, which pass the events on (ImGui_ImplGlfw_*Callback).
    ImGui_ImplGlfw_InitForOpenGL(window, false);
    ImGui_ImplOpenGL3_Init("#version 430 core");
    if (!options.replayPath.empty()) replay_.emplace(readEditorEvents(options.replayPath));
  }
  ~EditorLayer() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
  }
  EditorLayer(const EditorLayer&) = delete;
  EditorLayer& operator=(const EditorLayer&) = delete;

  SceneEditor& editor() { return editor_; }
  EditorRecorder* recorder() { return options_.recordPath.empty() ? nullptr : &recorder_; }
  bool capturesKeys() const { return ImGui::GetIO().WantCaptureKeyboard; }
  bool capturesMouse() const { return ImGui::GetIO().WantCaptureMouse; }

  // Starts the frame `frame` (counted from 1) with its input and draws the panel; `closes` is set when replayed
  // input closes the window.
  SceneEditor::Request beginFrame(int frame, bool running, const std::optional<ViewCamera>& view, bool& closes) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    closes = replay_ && replay_->apply(frame, editor_);
    ImGui::NewFrame();
    return editor_.draw(running, view);
  }
  void endFrame() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }
  void writeRecording() const {
    if (!options_.recordPath.empty()) recorder_.write(options_.recordPath);
  }

 private:
  ImGuiContextHolder context_;
  const ViewOptions& options_;
  SceneEditor editor_;
  std::optional<EditorReplay> replay_;
  EditorRecorder recorder_;
};

// What passes from one simulation of the window to the next (the editor runs each scene it is given afresh).
struct WindowState {
  int frame = 0;              // frames drawn
  bool editing = false;       // the editor's panel shown, the simulation paused at its start
  std::string sceneText;      // the editor's document the simulation was made from
  std::optional<OrbitCamera> orbit;
};

class Viewer {
 public:
  Viewer(const Scene& scene, const ViewOptions& options, GLFWwindow* window, const gl::ContextInfo& gl,
         EditorLayer* layer, WindowState& state)
      : scene_(withSpareBalls(scene)), firstSpareBall_(scene.rigidBodies.size()), options_(options), window_(window),
        layer_(layer), state_(state),
        snowballTemplate_(sampleSnowball()),
        session_(scene_, gl, sessionOptions(scene_, options, snowballTemplate_.size()), std::cerr), renderer_(scene_),
        orbit_(render::defaultCamera(scene_, float(options.widthPx) / float(options.heightPx)), scene_),
        accumulator_(scene.time.dtS, 1), colorMode_(options.colorMode),
        renderMode_(session_.pictureRenderMode(options.renderMode)) {
    // The surface is made (and reported) with the rest of the start.
    if (renderMode_ == render::RenderMode::Surface) session_.surface();
    if (state_.orbit) orbit_ = state_.orbit->of(scene_);
    liveText_ = state_.sceneText;
    // The session has just built the simulation at its start: editing needs no reset.
    setEditing(state_.editing, false);
    if (layer_ && editing_) measureStepCost();
    installCallbacks();
    std::printf("firn view: %s, %s particles; drag to orbit (right or shift-drag: pan, wheel: zoom); space pause, "
                "S step, R reset, +/- speed, C colour, V particles/surface, B domain box, T throw a snowball, "
                "O throw a ball, F reframe, %sQ quit\n",
                scene.name.empty() ? "scene" : scene.name.c_str(),
                withThousands(double(session_.seeds().size())).c_str(), layer_ ? "Tab edit/run, " : "");
  }

  // Runs until the window closes (or the scripted frames end): nothing; or until the editor runs a scene other than
  // this simulation's: that scene.
  std::optional<Scene> run() {
    auto lastFrame = Clock::now();
    auto lastTitle = lastFrame;
    int& frame = state_.frame;
    while (glfwWindowShouldClose(window_) == GLFW_FALSE) {
      glfwPollEvents();
      if (layer_) {
        bool closes = false;
        const SceneEditor::Request request = layer_->beginFrame(frame + 1, !editing_, editorView(), closes);
        if (closes) requestClose();
        std::optional<Scene> next = follow(request);
        if (!editing_) applyLiveEdits();
        // While editing, the view shows the scene as the edits leave it, once they settle.
        std::string settledText;
        if (!next && editing_) {
          if (std::optional<Scene> settled = layer_->editor().settledScene(settledText)) {
            if (settledText != state_.sceneText) {
              state_.sceneText = settledText;
              next = std::move(settled);
            }
          }
        }
        if (next) {
          ImGui::EndFrame();
          state_.orbit = orbit_;
          return next;
        }
      }
      const auto now = Clock::now();
      const double frameWallS = std::chrono::duration<double>(now - lastFrame).count();
      lastFrame = now;

      const int steps = paused_ ? std::exchange(pendingSingleSteps_, 0) : accumulator_.stepsForFrame(frameWallS, speed_);
      advance(steps);

      glm::ivec2 framebufferPx;
      glfwGetFramebufferSize(window_, &framebufferPx.x, &framebufferPx.y);
      // A minimised window has no pixels to draw into.
      // While editing, the view lies beside the editor's panel.
      const int panelPx = editing_ ? std::min(SceneEditor::panelWidthPx(window_), framebufferPx.x - 1) : 0;
      const glm::ivec2 viewPx(framebufferPx.x - panelPx, framebufferPx.y);
      if (viewPx.x > 0 && viewPx.y > 0) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (panelPx > 0) {
          // The panel's side too: the view's drawing leaves it as the last frame left it.
          glViewport(0, 0, framebufferPx.x, framebufferPx.y);
          glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
          glClear(GL_COLOR_BUFFER_BIT);
        }
        renderer_.setViewportOrigin({panelPx, 0});
        renderer_.draw(simulation().particleView(), shownBodyPoses(), orbit_.camera(), viewPx, colorMode_,
                       currentSurface());
      }
      if (layer_) layer_->endFrame();
      ++frame;
      if (std::count(options_.throwAtFrames.begin(), options_.throwAtFrames.end(), frame) > 0) throwSnowball();
      if (options_.frames && frame >= *options_.frames) {
        // A scripted window waits for the run it started headless.
        if (layer_) layer_->editor().finishHeadlessRun();
        if (!options_.screenshotPath.empty()) {
          render::writePng(options_.screenshotPath, render::readFramebuffer(framebufferPx));
          std::printf("firn view: wrote %s\n", options_.screenshotPath.string().c_str());
        }
        std::printf("firn view: %d frames, %llu steps, t = %.4f s, %zu particles\n", frame,
                    static_cast<unsigned long long>(simulation().stepCount()), simulation().timeS(),
                    simulation().particleCount());
        break;
      }
      glfwSwapBuffers(window_);
      if (std::chrono::duration<double>(now - lastTitle).count() >= kTitleIntervalS) {
        updateTitle(std::chrono::duration<double>(now - lastTitle).count());
        lastTitle = now;
      }
    }
    return std::nullopt;
  }

 private:
  // The window's callbacks: each event to the editor's panel first, where there is one, and to the view when the
  // panel does not take it.
  void installCallbacks() {
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int scancode, int action, int mods) {
      Viewer& viewer = *static_cast<Viewer*>(glfwGetWindowUserPointer(w));
      if (viewer.layer_) {
        ImGui_ImplGlfw_KeyCallback(w, key, scancode, action, mods);
        if (EditorRecorder* recorder = viewer.layer_->recorder(); recorder && action == GLFW_PRESS) {
          recorder->key(viewer.state_.frame + 1, key, mods);
        }
        if (viewer.layer_->capturesKeys()) return;
      }
      if (action != GLFW_RELEASE) viewer.onKey(key, mods);
    });
    glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned codepoint) {
      Viewer& viewer = *static_cast<Viewer*>(glfwGetWindowUserPointer(w));
      if (!viewer.layer_) return;
      ImGui_ImplGlfw_CharCallback(w, codepoint);
      if (EditorRecorder* recorder = viewer.layer_->recorder()) recorder->text(viewer.state_.frame + 1, codepoint);
    });
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int mods) {
      Viewer& viewer = *static_cast<Viewer*>(glfwGetWindowUserPointer(w));
      if (!viewer.layer_) return;
      ImGui_ImplGlfw_MouseButtonCallback(w, button, action, mods);
      // A press on the selected part's handles drags them, not the view.
      if (button == GLFW_MOUSE_BUTTON_LEFT) {
        const ImVec2 cursorPx(float(viewer.cursorX_), float(viewer.cursorY_));
        viewer.handleHeld_ = action == GLFW_PRESS && viewer.editing_ && viewer.layer_->editor().holdsPointer(cursorPx);
      }
      if (EditorRecorder* recorder = viewer.layer_->recorder()) {
        recorder->button(viewer.state_.frame + 1, viewer.cursorX_, viewer.cursorY_, button, action == GLFW_PRESS);
      }
    });
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
      Viewer& viewer = *static_cast<Viewer*>(glfwGetWindowUserPointer(w));
      const bool dragging = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS ||
                            glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
      if (viewer.layer_ && viewer.layer_->recorder() && dragging) {
        viewer.layer_->recorder()->move(viewer.state_.frame + 1, x, y);
      }
      const bool panelHasIt = viewer.layer_ && (viewer.layer_->capturesMouse() || viewer.handleHeld_);
      viewer.onCursor(x, y, !panelHasIt);
    });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double x, double y) {
      Viewer& viewer = *static_cast<Viewer*>(glfwGetWindowUserPointer(w));
      if (viewer.layer_) {
        ImGui_ImplGlfw_ScrollCallback(w, x, y);
        if (viewer.layer_->capturesMouse()) return;
      }
      viewer.orbit_.zoom(y);
    });
    // ImGui's backend follows the pointer only while the window has the focus and the pointer: it is told both.
    glfwSetWindowFocusCallback(window_, [](GLFWwindow* w, int focused) {
      if (static_cast<Viewer*>(glfwGetWindowUserPointer(w))->layer_) ImGui_ImplGlfw_WindowFocusCallback(w, focused);
    });
    glfwSetCursorEnterCallback(window_, [](GLFWwindow* w, int entered) {
      if (static_cast<Viewer*>(glfwGetWindowUserPointer(w))->layer_) ImGui_ImplGlfw_CursorEnterCallback(w, entered);
    });
    glfwSetWindowCloseCallback(window_, [](GLFWwindow* w) {
      Viewer& viewer = *static_cast<Viewer*>(glfwGetWindowUserPointer(w));
      glfwSetWindowShouldClose(w, GLFW_FALSE);
      if (viewer.layer_ && viewer.layer_->recorder()) viewer.layer_->recorder()->close(viewer.state_.frame + 1);
      viewer.requestClose();
    });
  }

  // While running: a settled edit of the materials alone goes to the simulation at once (Simulation::setMaterials),
  // where the step can take it; the panel says what became of it.
  void applyLiveEdits() {
    std::string text;
    const std::optional<Scene> settled = layer_->editor().settledScene(text);
    if (!settled || text == liveText_) return;
    liveText_ = text;
    if (text == state_.sceneText) return;
    json::Json edited = json::Json::parse(text), running = json::Json::parse(state_.sceneText);
    edited.erase("materials");
    running.erase("materials");
    if (edited != running) {
      layer_->editor().noteLive("The edits beyond the materials apply when you go back to editing (Tab).");
      return;
    }
    try {
      simulation().setMaterials(settled->materials);
      liveMaterials_ = settled->materials;
      char note[96];
      std::snprintf(note, sizeof note, "The materials as edited apply from t = %.4f s.", simulation().timeS());
      layer_->editor().noteLive(note);
      std::printf("firn view: %s\n", note);
    } catch (const InputError& error) {
      layer_->editor().noteLive(std::string("Not live: ") + error.what());
    } catch (const SimulationError& error) {
      std::fprintf(stderr, "firn view: %s\nfirn view: paused; press R to reset\n", error.what());
      unstable_ = true;
      paused_ = true;
    }
  }

  // How fast the scene the editor shows steps here, before it runs: a few steps timed from its start, which is then
  // put back (Simulation::saveState), so the panel can say it (SceneEditor::noteStepCost). The first step is left
  // out of the time: a driver may compile the passes at their first dispatch.
  void measureStepCost() {
    constexpr int kTimedSteps = 3;
    if (simulation().particleCount() == 0) return;
    simulation().saveState();
    simulation().step(scene_.time.dtS);
    glFinish();
    const auto start = Clock::now();
    for (int s = 0; s < kTimedSteps; ++s) simulation().step(scene_.time.dtS);
    glFinish();
    const double msPerStep = 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / kTimedSteps;
    simulation().restoreState();
    layer_->editor().noteStepCost(msPerStep, simulation().particleCount());
  }

  // Where the editor's view of the scene lies in the window, beside its panel, and its camera; none while running.
  std::optional<ViewCamera> editorView() const {
    if (!editing_) return std::nullopt;
    int widthPx = 0, heightPx = 0;
    glfwGetWindowSize(window_, &widthPx, &heightPx);
    const float panelPx = std::min(SceneEditor::kPanelWidthPx, float(widthPx));
    if (float(widthPx) <= panelPx || heightPx <= 0) return std::nullopt;
    return ViewCamera{orbit_.camera(), ImVec2(panelPx, 0), ImVec2(float(widthPx) - panelPx, float(heightPx))};
  }

  // Closes the window, unless the editor holds changes not saved: then it asks first (SceneEditor::closeRequested).
  void requestClose() {
    if (!layer_ || quitting_ || layer_->editor().closeRequested()) glfwSetWindowShouldClose(window_, GLFW_TRUE);
  }

  // Editing: the simulation back at its start and paused, the domain's box shown; running: the box as asked.
  void setEditing(bool editing, bool reset = true) {
    editing_ = editing;
    state_.editing = editing;
    if (editing) {
      liveMaterials_.reset();  // the document's edits make the next simulation
      if (reset) resetSimulation();
      paused_ = true;
    }
    renderer_.setDomainEdges(editing || options_.domainBox);
  }

  // Does what the editor's panel asked; returns the scene to run when it is not this simulation's.
  std::optional<Scene> follow(SceneEditor::Request request) {
    switch (request) {
      case SceneEditor::Request::None: break;
      case SceneEditor::Request::Edit:
        // What the run cost, for the editor's estimate of the next.
        if (stepCostS_ > 0) layer_->editor().noteStepCost(stepCostS_ * 1e3, simulation().particleCount());
        setEditing(true);
        break;
      case SceneEditor::Request::Quit:
        quitting_ = true;
        glfwSetWindowShouldClose(window_, GLFW_TRUE);
        break;
      case SceneEditor::Request::Run: {
        std::optional<Scene> scene = layer_->editor().runnableScene();
        if (!scene) {
          std::printf("firn view: cannot run: %s\n", layer_->editor().problemMessage().value_or("").c_str());
          break;
        }
        const std::string text = layer_->editor().document().json().dump();
        state_.editing = false;
        if (text != state_.sceneText) {
          state_.sceneText = text;
          return scene;
        }
        setEditing(false);
        paused_ = false;
        accumulator_.reset();
        break;
      }
    }
    return std::nullopt;
  }

  // The session the command line asks for: room for the snowballs, in the budget and in the particle buffers;
  // a surface asked for on the command line checked before the simulation is built (bad settings are exit 2).
  static SessionOptions sessionOptions(const Scene& scene, const ViewOptions& options, std::size_t snowballParticles) {
    SessionOptions session;
    session.messagePrefix = "firn view";
    session.showProgress = options.showProgress;
    session.withSurface = options.renderMode == render::RenderMode::Surface;
    session.reservedParticles = kSnowballCapacity * estimateBody(snowballBody(scene), scene.grid).particles;
    session.addedParticleCapacity = kSnowballCapacity * snowballParticles;
    session.transferShapes = options.transferShapes;
    return session;
  }

  Simulation& simulation() { return session_.simulation(); }

  // The rigid bodies to draw: the scene's and the balls thrown so far, not the spares still parked.
  std::vector<ObjectPose> shownBodyPoses() {
    std::vector<ObjectPose> poses = simulation().rigidBodyPoses();
    poses.resize(std::min(poses.size(), firstSpareBall_ + ballsThrown_));
    return poses;
  }

  void resetSimulation() {
    session_.restart();  // parks the thrown balls again
    // The materials edited live stay, while running; editing starts from the file's.
    if (liveMaterials_ && !editing_) simulation().setMaterials(*liveMaterials_);
    ballsThrown_ = 0;
    accumulator_.reset();
    unstable_ = false;
    surfaceIsCurrent_ = false;
  }

  // In surface mode, the surface of the particles as they are, rebuilt when they or the colours changed.
  const surface::SurfaceReconstruction* currentSurface() {
    if (renderMode_ != render::RenderMode::Surface) return nullptr;
    surface::SurfaceReconstruction& surface = session_.surface();
    const SurfaceKey key{simulation().stepCount(), simulation().particleCount(), colorMode_};
    if (!surfaceIsCurrent_ || !(key == surfaceKey_)) {
      surface.reconstruct(simulation().particleView(), renderer_.particleColors(simulation().particleView(), colorMode_));
      surfaceKey_ = key;
      surfaceIsCurrent_ = true;
    }
    return &surface;
  }

  void switchRenderMode() {
    if (renderMode_ == render::RenderMode::Surface) {
      renderMode_ = render::RenderMode::Particles;
      return;
    }
    try {
      session_.surface();
      renderMode_ = render::RenderMode::Surface;
      surfaceIsCurrent_ = false;
    } catch (const InputError& error) {
      std::fprintf(stderr, "firn view: no surface: %s\n", error.what());
    }
  }

  // Takes `steps` steps of dt, then reads the watchdog; a scripted run stops on instability, an interactive
  // one pauses with the message so the user can look, then reset.
  void advance(int steps) {
    if (steps <= 0 || unstable_) return;
    const auto start = Clock::now();
    // The accumulator counts steps of dt; an adaptive scene covers that time in steps of its own choosing.
    steps = simulation().advanceTo(simulation().timeS() + steps * scene_.time.dtS);
    try {
      simulation().checkWatchdog();  // reads a small buffer, which waits for the steps to finish
    } catch (const SimulationError& error) {
      if (options_.frames) throw;
      std::fprintf(stderr, "firn view: %s\nfirn view: paused; press R to reset\n", error.what());
      unstable_ = true;
      paused_ = true;
    }
    const double secondsPerStep = std::chrono::duration<double>(Clock::now() - start).count() / std::max(steps, 1);
    // The cap follows the measured cost of a step (smoothed), so physics fits its share of each frame.
    stepCostS_ = stepCostS_ == 0 ? secondsPerStep : 0.8 * stepCostS_ + 0.2 * secondsPerStep;
    accumulator_.setMaxStepsPerFrame(std::max(1, int(kPhysicsBudgetPerFrameS / stepCostS_)));
    stepsSinceTitle_ += steps;
  }

  void updateTitle(double intervalS) {
    char text[512];
    const double stepsPerS = stepsSinceTitle_ / intervalS;
    std::snprintf(text, sizeof text,
                  "Firn — %s | %.0f steps/s, %.2f ms/step | %s particles | t = %.3f s | speed %g× | %s, colour: %s%s",
                  scene_.name.empty() ? "scene" : scene_.name.c_str(), stepsPerS, stepCostS_ * 1e3,
                  withThousands(double(simulation().particleCount())).c_str(), simulation().timeS(), speed_,
                  render::renderModeName(renderMode_), render::colorModeName(colorMode_),
                  unstable_  ? " | UNSTABLE (R resets)"
                  : editing_ ? " | editing (Tab runs)"
                  : paused_  ? " | paused"
                             : "");
    glfwSetWindowTitle(window_, text);
    stepsSinceTitle_ = 0;
  }

  void onKey(int key, int mods) {
    // While editing, the simulation stays at its start: only the window's and the camera's keys.
    const bool viewKey = key == GLFW_KEY_ESCAPE || key == GLFW_KEY_Q || key == GLFW_KEY_F || key == GLFW_KEY_B ||
                         key == GLFW_KEY_C || key == GLFW_KEY_V;
    if (editing_ && !viewKey) return;
    switch (key) {
      case GLFW_KEY_ESCAPE:
      case GLFW_KEY_Q: requestClose(); break;
      case GLFW_KEY_SPACE: paused_ = !paused_ || unstable_; accumulator_.reset(); break;
      case GLFW_KEY_S:
      case GLFW_KEY_RIGHT:
        paused_ = true;
        ++pendingSingleSteps_;
        break;
      case GLFW_KEY_R: resetSimulation(); break;
      case GLFW_KEY_EQUAL:
      case GLFW_KEY_KP_ADD: speed_ = std::min(speed_ * 2, kMaxSpeed); break;
      case GLFW_KEY_MINUS:
      case GLFW_KEY_KP_SUBTRACT: speed_ = std::max(speed_ / 2, kMinSpeed); break;
      case GLFW_KEY_C: {
        const int next = (int(colorMode_) + ((mods & GLFW_MOD_SHIFT) ? render::kColorModeCount - 1 : 1)) %
                         render::kColorModeCount;
        colorMode_ = render::ColorMode(next);
        break;
      }
      case GLFW_KEY_V: switchRenderMode(); break;
      case GLFW_KEY_B: renderer_.setDomainEdges(!renderer_.domainEdges()); break;
      case GLFW_KEY_T: throwSnowball(); break;
      case GLFW_KEY_O: throwRigidBall(); break;
      case GLFW_KEY_F: orbit_ = OrbitCamera(render::defaultCamera(scene_, aspect()), scene_); break;
      default: break;
    }
  }

  // The pointer moved; `toView`: the editor's panel does not take it, and a drag turns or pans the camera.
  void onCursor(double x, double y, bool toView) {
    const double dx = x - cursorX_, dy = y - cursorY_;
    cursorX_ = x;
    cursorY_ = y;
    if (!toView) return;
    const bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    const bool right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                       glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
    const bool shift = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                       glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    int widthPx = 0, heightPx = 0;
    glfwGetWindowSize(window_, &widthPx, &heightPx);
    if (right || (left && shift)) {
      orbit_.pan(dx, dy, heightPx);
    } else if (left) {
      orbit_.orbit(dx, dy);
    }
  }

  float aspect() const {
    int widthPx = 0, heightPx = 0;
    glfwGetFramebufferSize(window_, &widthPx, &heightPx);
    return heightPx > 0 ? float(widthPx) / float(heightPx) : 1.0f;
  }

  // The snowball, centred at the origin, at rest.
  std::vector<ParticleSeed> sampleSnowball() const {
    Scene ball = scene_;
    const Body body = snowballBody(scene_);
    ball.bodies = {body};
    std::vector<ParticleSeed> particles = sampleBodies(ball);
    for (ParticleSeed& particle : particles) {
      particle.positionM -= glm::vec3(body.centerM);
      particle.bodyIndex = -1;
    }
    return particles;
  }

  // Where a thrown ball starts and how fast it goes: along the view direction from where the view ray enters the
  // domain (or from the camera, if it is inside), kept clear of the walls; nothing if the domain is too small for it.
  struct Throw {
    glm::vec3 centerM;
    glm::vec3 velocityMPerS;
  };
  std::optional<Throw> aimThrow() const {
    const render::Camera camera = orbit_.camera();
    const glm::vec3 forward = glm::normalize(camera.targetM - camera.positionM);
    const float clearanceM = float((kSnowballRadiusCells + 1) * scene_.grid.cellSizeM);
    const glm::vec3 lowM = glm::vec3(scene_.grid.interiorMinM()) + clearanceM;
    const glm::vec3 highM = glm::vec3(scene_.grid.interiorMaxM()) - clearanceM;
    if (glm::any(glm::greaterThan(lowM, highM))) return std::nullopt;
    const std::optional<float> entry = rayEntersBox(camera.positionM, forward, lowM, highM);
    const glm::vec3 centerM = glm::clamp(entry ? camera.positionM + *entry * forward : camera.targetM, lowM, highM);
    // At most a third of a cell per step, well inside the CFL bound the watchdog enforces.
    const float speedMPerS = float(std::min(kSnowballSpeedMPerS, scene_.grid.cellSizeM / scene_.time.dtS / 3));
    return Throw{centerM, speedMPerS * forward};
  }

  void throwSnowball() {
    if (simulation().particleCount() + snowballTemplate_.size() > simulation().particleCapacity()) {
      std::fprintf(stderr, "firn view: no room for another snowball (%d thrown; press R to reset)\n", kSnowballCapacity);
      return;
    }
    const std::optional<Throw> aim = aimThrow();
    if (!aim) return;
    // The fixed-point scale allows no particle heavier than the scene's heaviest (a points body may bring
    // lighter particles than ρ s³): such a snowball is made lighter instead.
    const float maxMassKg = float(simulation().fixedPoint().referenceMassKg);
    std::vector<ParticleSeed> particles = snowballTemplate_;
    for (ParticleSeed& particle : particles) {
      particle.positionM += aim->centerM;
      particle.velocityMPerS = aim->velocityMPerS;
      particle.massKg = std::min(particle.massKg, maxMassKg);
    }
    simulation().addParticles(particles);
  }

  // Sets the next parked ball going, as a snowball is thrown, unturned and not spinning.
  void throwRigidBall() {
    if (ballsThrown_ == kRigidBallCapacity) {
      std::fprintf(stderr, "firn view: no ball left to throw (%zu thrown; press R to reset)\n", kRigidBallCapacity);
      return;
    }
    const std::optional<Throw> aim = aimThrow();
    if (!aim) return;
    ObjectPose pose;
    pose.positionM = aim->centerM;
    pose.velocityMPerS = aim->velocityMPerS;
    simulation().launchRigidBody(firstSpareBall_ + ballsThrown_, pose);
    ++ballsThrown_;
  }

  const Scene scene_;                // the file's, with the spare balls (withSpareBalls)
  const std::size_t firstSpareBall_;  // the spare balls' first index in scene_.rigidBodies
  std::size_t ballsThrown_ = 0;
  const ViewOptions& options_;
  GLFWwindow* window_;
  EditorLayer* layer_;  // the editor's panel, or none
  WindowState& state_;
  std::vector<ParticleSeed> snowballTemplate_;
  SimulationSession session_;
  render::Renderer renderer_;
  OrbitCamera orbit_;
  StepAccumulator accumulator_;
  render::ColorMode colorMode_;
  render::RenderMode renderMode_;
  // What the surface was last rebuilt from.
  struct SurfaceKey {
    std::uint64_t step;
    std::size_t particles;
    render::ColorMode colorMode;
    bool operator==(const SurfaceKey& other) const {
      return step == other.step && particles == other.particles && colorMode == other.colorMode;
    }
  };
  SurfaceKey surfaceKey_{0, 0, render::ColorMode::Material};
  bool surfaceIsCurrent_ = false;
  bool paused_ = false;
  bool editing_ = false;
  bool handleHeld_ = false;  // the left button went down on the editor's handles
  std::string liveText_;     // the editor's document last looked at while running
  std::optional<std::vector<Material>> liveMaterials_;  // the materials it applied live
  bool quitting_ = false;  // the editor's dialog answered: close without asking again
  bool unstable_ = false;
  int pendingSingleSteps_ = 0;
  double speed_ = 1;
  double stepCostS_ = 0;
  int stepsSinceTitle_ = 0;
  double cursorX_ = 0, cursorY_ = 0;
};

}  // namespace

void runViewer(const Scene& scene, const ViewOptions& options) {
  GlfwSession glfw;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  const std::string title = "Firn — " + (scene.name.empty() ? std::string("scene") : scene.name);
  WindowPtr window(glfwCreateWindow(options.widthPx, options.heightPx, title.c_str(), nullptr, nullptr));
  if (!window) {
    throw NoOpenGLError("could not open a window with an OpenGL 4.3 core context: " + lastGlfwError());
  }
  glfwMakeContextCurrent(window.get());
  glfwSwapInterval(1);
  gl::ContextInfo info;
  info.platform = "GLFW window";
  gl::loadGLFunctions(info);
  std::optional<EditorLayer> layer;
  WindowState state;
  if (options.edit) {
    layer.emplace(window.get(), options, info);
    state.editing = true;
    state.sceneText = layer->editor().document().json().dump();
  }
  // The editor runs each scene it is given in a simulation of its own; a scene that cannot start (a surface its
  // particles do not suit) leaves the last one, back at editing.
  std::optional<Scene> next = scene;
  Scene last = scene;
  std::string lastText = state.sceneText;
  bool first = true;
  while (next) {
    std::optional<Viewer> viewer;
    try {
      viewer.emplace(*next, options, window.get(), info, layer ? &*layer : nullptr, state);
    } catch (const InputError& error) {
      if (!layer || first) throw;
      std::fprintf(stderr, "firn view: cannot run: %s\n", error.what());
      // The editor holds it as its problem until the document changes, so that it is not tried again.
      layer->editor().noteStartFailure(state.sceneText, error.what());
      state.editing = true;
      state.sceneText = lastText;
      next = last;
      continue;
    }
    last = *next;
    lastText = state.sceneText;
    first = false;
    next = viewer->run();
  }
  if (layer) layer->writeRecording();
}

}  // namespace firn
