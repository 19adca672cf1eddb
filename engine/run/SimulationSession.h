#pragma once
// A scene made ready to simulate, the same way for `firn run` and `firn view`: the particles its bodies will make
// set against the budget (run/Budget.h), the bodies sampled within it (with a progress line on a terminal), the
// pre-flight checks (run/Preflight.h), the Simulation built, and its start reported: the scene, the pre-flight's
// notes and warnings. On request, the surface reconstruction of its particles. The two commands then differ only
// in what they do with each frame: write files (run/HeadlessRun.h) or draw a window (apps/firn/Viewer.h).
#include <cstddef>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gl/Context.h"
#include "run/Preflight.h"
#include "scene/Scene.h"
#include "sim/SceneUpload.h"

namespace firn {

class DomainShare;
class Simulation;
namespace surface {
class SurfaceReconstruction;
}
namespace render {
enum class RenderMode;
}

struct SessionOptions {
  std::string messagePrefix = "firn";    // what each message starts with: "firn", "firn view"
  bool showProgress = false;             // progress on stderr while sampling (run/Progress.h)
  std::optional<int> lastFrame;          // the run's last frame: the opening line and the emitters' notes say it
  bool withSurface = false;              // the surface's settings checked against the particles before simulating
  double reservedParticles = 0;          // the budget's room for particles added while running (an estimate)
  std::size_t addedParticleCapacity = 0; // the particle buffers' room for them, beyond the bodies' particles
  DomainShare* share = nullptr;          // the part of the domain this process simulates (sim/DomainShare.h), or all
  std::string transferShapes;            // the transfer shapes to time (SimulationOptions); empty: every shape
};

// What a session says of a scene as it starts, a line each without the message prefix: the opening line (its name,
// particles, cells, dt, the run's frames and the renderer), the pre-flight's notes, and its warnings ("warning: …").
std::vector<std::string> startLines(const Scene& scene, std::size_t particles, const PreflightReport& report,
                                    const gl::ContextInfo& gl, std::optional<int> lastFrame);

// What a scene would start with, found as a session finds it but without building the simulation (the scene
// editor's numbers before running): the budget, the bodies sampled within it, and the pre-flight.
struct StartNumbers {
  std::vector<std::string> lines;  // startLines
  std::size_t particles = 0;       // the bodies' particles
  std::size_t maxParticles = 0;    // what the budget leaves for them (run/Budget.h)
  std::string limit;               // the limit that binds, in words
  double stableDtS = 0;            // the pre-flight's bound on the step
};
// Throws InputError as a session would (over the budget, refused by the pre-flight).
StartNumbers numbersBeforeRunning(const Scene& scene, const gl::ContextInfo& gl, const SessionOptions& options);

class SimulationSession {
 public:
  // Throws InputError (exit 2) for a scene over the budget, one the pre-flight refuses or, with withSurface, one
  // whose surface settings do not suit its particles; NoOpenGLError when the driver lacks what the simulation needs.
  SimulationSession(const Scene& scene, const gl::ContextInfo& gl, const SessionOptions& options, std::ostream& log);
  ~SimulationSession();
  SimulationSession(const SimulationSession&) = delete;
  SimulationSession& operator=(const SimulationSession&) = delete;

  const std::vector<ParticleSeed>& seeds() const { return seeds_; }
  Simulation& simulation() { return *simulation_; }

  // Back to the initial state: a new Simulation of the same particles, the old one's buffers freed first.
  void restart();

  // The surface reconstruction, made and reported on first use. Throws InputError naming surface.resolution or
  // surface.smoothing when the scene's settings do not suit its particles.
  surface::SurfaceReconstruction& surface();

  // How the pictures draw the snow: `asked`, or when nothing was asked its surface, the look of snow, unless the
  // scene's surface settings do not suit its particles (checkKernelRange): then its particles, with a one-line note
  // in the log saying why. Asked for, a surface that does not suit stays an error, raised by surface().
  render::RenderMode pictureRenderMode(std::optional<render::RenderMode> asked);

 private:
  const Scene& scene_;
  gl::ContextInfo gl_;
  std::string messagePrefix_;
  std::ostream& log_;
  std::vector<ParticleSeed> seeds_;
  std::size_t particleCapacity_;
  DomainShare* share_;
  std::string transferShapes_;
  ColliderFields colliderFields_;  // baked once, for the pre-flight and every restart
  std::unique_ptr<Simulation> simulation_;
  std::unique_ptr<surface::SurfaceReconstruction> surface_;
};

}  // namespace firn
