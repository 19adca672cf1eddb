#include "run/SimulationSession.h"

#include <cstdio>
#include <functional>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>

#include "Error.h"
#include "render/Renderer.h"
#include "run/Budget.h"
#include "run/Progress.h"
#include "sim/DomainShare.h"
#include "sim/Simulation.h"
#include "surface/SurfaceReconstruction.h"

namespace firn {
namespace {

// sampleWithinBudget, with a progress line on stderr when asked.
std::vector<ParticleSeed> sampleShowingProgress(const Scene& scene, const gl::ContextInfo& gl,
                                                const SessionOptions& options) {
  std::optional<ProgressLine> progressLine;
  std::function<void(std::size_t, double)> progress;
  if (options.showProgress) {
    progressLine.emplace(stderr);
    progress = [&](std::size_t body, double fraction) {
      progressLine->showFraction(options.messagePrefix + ": sampling bodies[" + std::to_string(body) + "]:", fraction);
    };
  }
  return sampleWithinBudget(scene, gl, options.reservedParticles, progress, options.share ? options.share->shares() : 1);
}

}  // namespace

std::vector<std::string> startLines(const Scene& scene, std::size_t particles, const PreflightReport& report,
                                    const gl::ContextInfo& gl, std::optional<int> lastFrame) {
  std::ostringstream opening;
  opening << (scene.name.empty() ? std::string("scene") : scene.name) << ": " << particles << " particles, "
          << scene.grid.cells.x << "×" << scene.grid.cells.y << "×" << scene.grid.cells.z << " cells, dt "
          << scene.time.dtS << " s" << (lastFrame ? ", " + std::to_string(*lastFrame) + " frames" : std::string())
          << " on " << gl.renderer;
  std::vector<std::string> lines{opening.str()};
  lines.insert(lines.end(), report.notes.begin(), report.notes.end());
  for (const std::string& warning : report.warnings) lines.push_back("warning: " + warning);
  return lines;
}

StartNumbers numbersBeforeRunning(const Scene& scene, const gl::ContextInfo& gl, const SessionOptions& options) {
  const int shares = options.share ? options.share->shares() : 1;
  const ParticleBudget budget = checkParticleBudget(scene, gl, options.reservedParticles, shares);
  const std::vector<ParticleSeed> seeds = sampleWithinBudget(scene, budget, {});
  const PreflightReport report = preflight(scene, seeds, options.lastFrame);
  StartNumbers numbers;
  numbers.lines = startLines(scene, seeds.size(), report, gl, options.lastFrame);
  numbers.particles = seeds.size();
  numbers.maxParticles = budget.maxParticles;
  numbers.limit = budget.limit;
  numbers.stableDtS = report.stableDtS;
  return numbers;
}

SimulationSession::SimulationSession(const Scene& scene, const gl::ContextInfo& gl, const SessionOptions& options,
                                     std::ostream& log)
    : scene_(scene), gl_(gl), messagePrefix_(options.messagePrefix), log_(log),
      seeds_(sampleShowingProgress(scene, gl, options)), particleCapacity_(seeds_.size() + options.addedParticleCapacity),
      share_(options.share), transferShapes_(options.transferShapes), colliderFields_(bakeColliderFields(scene)) {
  // Before any simulation: a scene that cannot run says so at once (exit 2).
  const PreflightReport report = preflight(scene, seeds_, options.lastFrame, colliderFields_);
  // Surface settings that do not suit the particles are bad input before the GPU's buffers are made.
  if (options.withSurface) surface::checkKernelRange(scene, seeds_);
  restart();
  for (const std::string& line : startLines(scene, seeds_.size(), report, gl, options.lastFrame)) {
    log << messagePrefix_ << ": " << line << "\n";
  }
  log << messagePrefix_ << ": " << transfersLine(simulation_->transferShapeChoice()) << "\n";
}

SimulationSession::~SimulationSession() = default;

void SimulationSession::restart() {
  simulation_.reset();
  SimulationOptions options;
  options.particleCapacity = particleCapacity_;
  options.transferShapes = transferShapes_;
  options.share = share_;
  simulation_ = std::make_unique<Simulation>(scene_, seeds_, gl_, colliderFields_, options);
}

surface::SurfaceReconstruction& SimulationSession::surface() {
  if (surface_) return *surface_;
  const surface::KernelRange kernels = surface::checkKernelRange(scene_, seeds_);
  surface_ = std::make_unique<surface::SurfaceReconstruction>(scene_, seeds_, gl_);
  log_ << messagePrefix_ << ": surface: nodes " << kernels.cellM << " m apart (grid.cell_size / "
       << scene_.surface.resolution << "), kernel radius " << kernels.smallestM << "–" << kernels.largestM << " m ("
       << scene_.surface.smoothing << " particle spacings), iso " << scene_.surface.iso << "\n";
  return *surface_;
}

render::RenderMode SimulationSession::pictureRenderMode(std::optional<render::RenderMode> asked) {
  if (asked) return *asked;
  try {
    surface::checkKernelRange(scene_, seeds_);
  } catch (const InputError& unsuited) {
    log_ << messagePrefix_ << ": note: drawing the snow as particles, as its surface settings do not suit it: "
         << unsuited.what() << "\n";
    return render::RenderMode::Particles;
  }
  return render::RenderMode::Surface;
}

}  // namespace firn
