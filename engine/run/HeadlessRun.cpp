#include "run/HeadlessRun.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <ostream>
#include <string>
#include <system_error>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "Error.h"
#include "gl/Context.h"
#include "io/BodiesCsv.h"
#include "io/EnergyPlot.h"
#include "io/Checkpoint.h"
#include "io/OutputFolder.h"
#include "io/Ply.h"
#include "io/StatsCsv.h"
#include "io/SurfaceMesh.h"
#include "io/Text.h"
#include "io/Vdb.h"
#include "io/Video.h"
#include "run/Progress.h"
#include "run/RunRecord.h"
#include "run/SimulationSession.h"
#include "scene/SceneObjects.h"
#include "sim/DomainShare.h"
#include "sim/Simulation.h"
#include "surface/SurfaceReconstruction.h"
#include "voxelizer/Mesh.h"

namespace firn {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// <prefix>_NNNN<suffix>: frame_0001.ply, frame_0001.png, frame_0001_surface.ply, checkpoint_0010.firn, the names
// docs/command-line.md gives the outputs (and assembleVideo reads).
std::string numberedFileName(const char* prefix, int frame, const char* suffix) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%04d%s", prefix, frame, suffix);
  return name;
}

// llvmpipe's timer queries read nanoseconds for passes that take milliseconds (it runs a dispatch on the CPU
// outside the span its query records). A GPU's time is most of the wall time from dispatch to glFinish, short of the
// synchronisation's tens of microseconds; under a hundredth of it, the driver does not time the work, and the column
// says so rather than showing zeros.
bool driverReportsGpuTime(const std::vector<gl::PassTimer::PassTime>& passes) {
  constexpr double leastGpuShareOfWall = 0.01;
  double gpuMs = 0, wallMs = 0;
  for (const gl::PassTimer::PassTime& pass : passes) {
    gpuMs += pass.totalMs;
    wallMs += pass.totalWallMs;
  }
  return gpuMs >= leastGpuShareOfWall * wallMs;
}

void logPassTimes(const std::vector<gl::PassTimer::PassTime>& passes, double steps, std::ostream& log) {
  const bool gpuTime = driverReportsGpuTime(passes);
  for (const gl::PassTimer::PassTime& pass : passes) {
    char row[160];
    if (gpuTime) {
      std::snprintf(row, sizeof row, "  %-30s GPU %9.3f ms   wall %9.3f ms\n", pass.pass.c_str(), pass.totalMs / steps,
                    pass.totalWallMs / steps);
    } else {
      std::snprintf(row, sizeof row, "  %-30s GPU n/a   wall %9.3f ms\n", pass.pass.c_str(), pass.totalWallMs / steps);
    }
    log << row;
  }
  if (!passes.empty() && !gpuTime) {
    log << "  (GPU n/a: the driver reports no GPU time, its timer queries reading under 1% of the wall time; the wall "
           "times hold)\n";
  }
}

PointCache toPointCache(const ParticleSnapshot& particles) {
  PointCache cache;
  cache.positionsM.reserve(particles.size());
  cache.velocitiesMPerS.reserve(particles.size());
  cache.massesKg.reserve(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    cache.positionsM.emplace_back(particles.positionMass[i]);
    cache.velocitiesMPerS.emplace_back(particles.velocityVolume[i]);
    cache.massesKg.push_back(particles.positionMass[i].w);
  }
  cache.plasticJ = particles.plasticJ;
  return cache;
}

// Mass, momentum, centre of mass, mean J_P and the particles at the walls of a snapshot, summed in double; the
// energies are the audit's (sim/EnergyAudit.h).
FrameStats measureFrame(const ParticleSnapshot& particles, const GridSpec& grid, const EnergyBudget& energy) {
  FrameStats stats;
  // The walls act on grid nodes, so the particles they stop come to rest up to a cell short of the interior's
  // bounds (about half a cell for the quadratic kernel).
  const glm::dvec3 wallZoneLowM = grid.interiorMinM() + grid.cellSizeM;
  const glm::dvec3 wallZoneHighM = grid.interiorMaxM() - grid.cellSizeM;
  stats.particles = particles.size();
  double plasticJSum = 0;
  glm::dvec3 weightedPosition(0.0);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double mass = particles.positionMass[i].w;
    const glm::dvec3 velocity(particles.velocityVolume[i]);
    stats.massKg += mass;
    stats.momentumKgMPerS += mass * velocity;
    weightedPosition += mass * glm::dvec3(particles.positionMass[i]);
    plasticJSum += particles.plasticJ[i];
    const glm::dvec3 position(particles.positionMass[i]);
    if (glm::any(glm::lessThan(position, wallZoneLowM)) || glm::any(glm::greaterThan(position, wallZoneHighM))) {
      ++stats.particlesAtWalls;
    }
  }
  if (particles.size() > 0) {
    stats.meanPlasticJ = plasticJSum / double(particles.size());
    stats.centerOfMassM = weightedPosition / stats.massKg;
  }
  stats.kineticEnergyJ = energy.kineticJ;
  stats.potentialEnergyJ = energy.potentialJ;
  stats.elasticEnergyJ = energy.elasticJ;
  stats.bodiesKineticEnergyJ = energy.bodiesKineticJ;
  stats.bodiesPotentialEnergyJ = energy.bodiesPotentialJ;
  stats.colliderWorkJ = energy.colliderWorkJ;
  stats.arrivedEnergyJ = energy.arrivedJ;
  stats.wallsRemovedJ = energy.wallsRemovedJ;
  stats.hardeningEnergyJ = energy.hardeningJ;
  stats.couplingEnergyJ = energy.couplingJ;
  stats.stepEnergyJ = energy.stepTermJ;
  stats.dissipatedEnergyJ = energy.dissipatedJ;
  stats.energyCreatedJ = energy.createdJ;
  stats.energyToleranceJ = energy.toleranceJ;
  return stats;
}

// The objects bodies.csv and the object meshes follow: the rigid bodies and the colliders that move.
std::vector<SceneObject> movingObjects(const Scene& scene) {
  std::vector<SceneObject> objects = sceneObjects(scene);
  objects.erase(std::remove_if(objects.begin(), objects.end(), [](const SceneObject& object) { return !object.moves; }),
                objects.end());
  return objects;
}

// Each moving object's frame at `timeS`: a collider's from its motion, a rigid body's from `bodyPoses` (the
// simulation's, read back once per frame).
std::vector<ObjectPose> objectPoses(const Scene& scene, const std::vector<SceneObject>& objects,
                                    const std::vector<ObjectPose>& bodyPoses, double timeS) {
  std::vector<ObjectPose> poses;
  for (const SceneObject& object : objects) {
    poses.push_back(object.kind == ObjectKind::Collider
                        ? colliderObjectPose(scene.colliders[std::size_t(object.index)], timeS)
                        : bodyPoses.at(std::size_t(object.index)));
  }
  return poses;
}

std::string vectorText(const glm::dvec3& v) {
  return "(" + formatApproximately(v.x) + ", " + formatApproximately(v.y) + ", " + formatApproximately(v.z) + ")";
}

// A frame whose object has a pose that is not finite stops the run as the watchdog stops it for a particle
// (SimulationError, exit 3), before anything of the frame is written: its earlier frames stay on disk.
void requireFinitePoses(const std::vector<SceneObject>& objects, const std::vector<ObjectPose>& poses, int frame,
                        double timeS) {
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const ObjectPose& pose = poses[i];
    if (isFinite(pose)) continue;
    const glm::dquat& q = pose.orientation;
    throw SimulationError("the simulation became unstable:\n  - frame " + std::to_string(frame) + " (t = " +
                          formatApproximately(timeS) + " s): " + objects[i].name +
                          " became non-finite (NaN or Inf): position " + vectorText(pose.positionM) +
                          " m, orientation (" + formatApproximately(q.w) + ", " + formatApproximately(q.x) + ", " +
                          formatApproximately(q.y) + ", " + formatApproximately(q.z) + "), velocity " +
                          vectorText(pose.velocityMPerS) + " m/s, angular velocity " +
                          vectorText(pose.angularVelocityRadPerS) + " rad/s. Reduce time.dt.");
  }
}

// "colliders[1]" → "colliders_1": the stem of the object's mesh files, <stem>_NNNN.ply, whose last digits are the
// frame's alone, as sequence importers read them.
std::string meshFileStem(const std::string& objectName) {
  std::string stem;
  for (char c : objectName) {
    if (c == '[') {
      stem += '_';
    } else if (c != ']') {
      stem += c;
    }
  }
  return stem;
}

SurfaceMesh toSurfaceMesh(const voxelizer::TriangleMesh& mesh) {
  SurfaceMesh surface;
  surface.positionsM.reserve(mesh.vertices.size());
  for (const glm::dvec3& vertexM : mesh.vertices) surface.positionsM.emplace_back(vertexM);
  surface.indices.reserve(3 * mesh.triangles.size());
  for (const glm::uvec3& triangle : mesh.triangles) surface.indices.insert(surface.indices.end(), {triangle.x, triangle.y, triangle.z});
  return surface;
}

std::string progressText(int frame, int frames, double simulatedS, double stepsPerS, double etaS) {
  const int eta = static_cast<int>(etaS + 0.5);
  char text[128];
  std::snprintf(text, sizeof text, "firn: frame %d/%d  t = %.3f s  %.0f steps/s  ETA %d:%02d", frame, frames,
                simulatedS, stepsPerS, eta / 60, eta % 60);
  return text;
}

}  // namespace

// The session a run of `options` builds: the same for the run and for its check.
SessionOptions sessionOptionsFor(const RunOptions& options, int frames, DomainShare* share) {
  SessionOptions sessionOptions;
  sessionOptions.showProgress = options.showProgress;
  sessionOptions.lastFrame = frames;
  sessionOptions.withSurface =
      (options.writesPictures() && options.renderMode == render::RenderMode::Surface) || options.writesSurfaceCaches();
  sessionOptions.share = share;
  sessionOptions.transferShapes = options.transferShapes;
  return sessionOptions;
}

RunSummary runHeadless(const Scene& scene, const RunOptions& options, std::ostream& log, DomainShare* share) {
  const auto runStart = Clock::now();
  const int frames = options.frames.value_or(scene.time.frames);
  const bool writer = share == nullptr || share->writesOutput();
  // Held to the end of the run: no other run writes here meanwhile.
  std::optional<OutputFolderClaim> outputFolder;
  if (writer) outputFolder.emplace(options.outputDir);
  // Read before the context is made: a damaged checkpoint is refused at once.
  std::optional<Checkpoint> checkpoint;
  if (!options.resumePath.empty()) checkpoint = readCheckpoint(options.resumePath);

  // The context first: what its buffers hold is part of the estimate that precedes sampling.
  gl::HeadlessContext context(options.gpuOrdinal);
  const bool writePictures = options.writesPictures();
  const bool caches = options.writesSurfaceCaches();
  SimulationSession session(scene, context.info(), sessionOptionsFor(options, frames, share), log);
  const bool surfacePictures =
      writePictures && session.pictureRenderMode(options.renderMode) == render::RenderMode::Surface;
  Simulation& simulation = session.simulation();
  simulation.setPassTiming(options.passTimes);
  std::optional<render::OffscreenRenderer> pictures;
  render::Camera camera;
  if (writePictures && writer) {
    pictures.emplace(scene, options.imageSizePx);
    pictures->setDomainEdges(options.domainBox);
    camera = render::defaultCamera(scene, float(options.imageSizePx.x) / float(options.imageSizePx.y));
  }
  // Over several processes, what is drawn from the particles on the GPU is drawn by the writer, from every share's
  // particles gathered there (Simulation::gatherParticleView).
  const bool drawnFromParticles = surfacePictures || caches || writePictures;
  surface::SurfaceReconstruction* snowSurface = (surfacePictures || caches) && writer ? &session.surface() : nullptr;
  if (snowSurface) snowSurface->setPassTiming(options.passTimes);
  std::optional<StatsCsvWriter> stats;  // started once a checkpoint has been accepted
  const std::vector<SceneObject> objects = movingObjects(scene);
  std::optional<BodiesCsvWriter> bodies;  // with stats, when the scene has moving objects
  auto writeFrame = [&](int frame, std::uint64_t steps, double wallMs) {
    // The bodies' poses, one readback (none without bodies), for bodies.csv, the object meshes and the picture.
    const std::vector<ObjectPose> bodyPoses = simulation.rigidBodyPoses();
    const std::vector<ObjectPose> poses = objectPoses(scene, objects, bodyPoses, simulation.timeS());
    requireFinitePoses(objects, poses, frame, simulation.timeS());
    // Over several processes: every share's particles, gathered into the order of one process's (once: the snapshot
    // reads the view's copy when the pictures or caches need one).
    if (drawnFromParticles) simulation.gatherParticleView();
    const ParticleSnapshot particles = simulation.snapshot();
    const std::size_t activeBlocks = share ? share->activeBlocksInAll() : simulation.blockUsage().lastStep;
    if (!writer) return;
    FrameStats row = measureFrame(particles, scene.grid, simulation.energyBudget());
    row.frame = frame;
    row.timeS = simulation.timeS();
    row.steps = steps;
    row.wallMs = wallMs;
    row.activeBlocks = activeBlocks;
    const SolverSummary solves = simulation.takeSolverSummary();
    row.solverIterations = solves.mostIterations;
    row.solverResidual = solves.largestResidual;
    stats->write(row);
    if (bodies) {
      const std::vector<Simulation::ObjectLoadReading> loads = simulation.objectLoads();
      std::vector<ObjectFrameRow> rows;
      for (std::size_t i = 0; i < objects.size(); ++i) {
        ObjectFrameRow& objectRow = rows.emplace_back();
        objectRow.frame = frame;
        objectRow.timeS = simulation.timeS();
        objectRow.object = objects[i].name;
        objectRow.kind = objects[i].kind == ObjectKind::Collider ? "collider" : "rigid_body";
        objectRow.positionM = poses[i].positionM;
        objectRow.orientation = poses[i].orientation;
        objectRow.velocityMPerS = poses[i].velocityMPerS;
        objectRow.angularVelocityRadPerS = poses[i].angularVelocityRadPerS;
        // The collider table holds the colliders, then the rigid bodies.
        const std::size_t entry = std::size_t(objects[i].index) +
                                  (objects[i].kind == ObjectKind::RigidBody ? scene.colliders.size() : 0);
        objectRow.forceN = loads[entry].forceN;
        objectRow.workJ = loads[entry].workJ;
      }
      bodies->write(rows);
    }
    if (options.writeMesh) {
      for (std::size_t i = 0; i < objects.size(); ++i) {
        writeMeshPly(options.outputDir / numberedFileName(meshFileStem(objects[i].name).c_str(), frame, ".ply"),
                     toSurfaceMesh(posedMesh(objects[i].meshM, poses[i])),
                     objects[i].name + " at frame " + std::to_string(frame));
      }
    }
    if (options.writePly) writePly(options.outputDir / numberedFileName("frame", frame, ".ply"), toPointCache(particles));
    if (snowSurface) {
      snowSurface->reconstruct(
          simulation.particleView(),
          surfacePictures ? pictures->particleColors(simulation.particleView(), options.colorMode) : nullptr,
          caches ? surface::Velocities::Sum : surface::Velocities::Skip);
      if (caches) {
        VdbFrame cache;
        cache.isoLevel = float(scene.surface.iso);
        cache.surface = snowSurface->readMesh();
        cache.frame = frame;
        cache.timeS = simulation.timeS();
        if (options.writeMesh) writeMeshPly(options.outputDir / numberedFileName("frame", frame, "_surface.ply"), cache.surface);
        if (options.writeVdb) {
          cache.density = snowSurface->readDensity();
          cache.velocityMPerS = snowSurface->readVelocities();
          writeVdb(options.outputDir / numberedFileName("frame", frame, ".vdb"), cache);
        }
      }
    }
    if (pictures) {
      render::writePng(options.outputDir / numberedFileName("frame", frame, ".png"),
                       pictures->render(simulation.particleView(), bodyPoses, camera,
                                        options.colorMode, surfacePictures ? snowSurface : nullptr));
    }
  };

  RunSummary summary;
  summary.particles = session.seeds().size();
  summary.renderer = context.info().renderer;
  // A resumed run takes up at the checkpoint's frame, which it writes again (the same state, so the same file).
  int firstFrame = 0;
  const std::filesystem::path statsPath = options.outputDir / "stats.csv";
  const std::filesystem::path bodiesPath = options.outputDir / "bodies.csv";
  if (checkpoint) {
    simulation.resume(*checkpoint, options.resumePath);
    firstFrame = checkpoint->frame;
    checkpoint.reset();  // its buffers are on the GPU now
    summary.firstFrame = firstFrame;
    summary.frames = firstFrame;
    log << "firn: resumed at frame " << firstFrame << " (t = " << simulation.timeS() << " s) from "
        << options.resumePath.string() << "\n";
    // Resumed in its own folder, the run keeps the rows before its checkpoint; elsewhere stats.csv starts at the
    // checkpoint's frame.
    std::error_code error;
    const bool ownFolder = std::filesystem::equivalent(std::filesystem::absolute(options.resumePath).parent_path(),
                                                       options.outputDir, error);
    if (ownFolder) {
      stats.emplace(statsPath, firstFrame);
      if (!objects.empty()) bodies.emplace(bodiesPath, firstFrame);
    }
  }
  if (!stats && writer) stats.emplace(statsPath);
  if (!bodies && !objects.empty() && writer) bodies.emplace(bodiesPath);
  // run.json: written now, as the run starts, and again when it ends, saying how.
  std::optional<RunRecord> record;
  if (writer) {
    record.emplace(options.outputDir / "run.json", scene, options.commandLine, context.info(),
                   share ? share->shares() : 1);
    record->setSceneFingerprint(simulation.fingerprint());
    record->setTransfers(simulation.transferShapeChoice());
    record->setProgress(firstFrame, firstFrame, 0, summary.particles, secondsSince(runStart));
    record->write();
  }
  // The end, however it comes: run.json's exit, and the plot of the energy up to there (a run that failed keeps its
  // own error: a plot that cannot be drawn then is said, not thrown).
  const auto finish = [&](int status, const std::string& message) {
    if (!writer) return;
    record->setTransfers(simulation.transferShapeChoice());
    record->setProgress(summary.firstFrame, summary.frames, summary.steps, summary.particles, secondsSince(runStart));
    record->setExit(status, message);
    record->write();
    if (!options.writePlot) return;
    try {
      plotEnergy(statsPath, options.outputDir, (scene.name.empty() ? sceneFileName(scene) : scene.name) + ": energy");
      log << "firn: wrote " << (options.outputDir / "energy.png").string() << "\n";
    } catch (const InputError& error) {
      if (status != 0) {
        log << "firn: " << error.what() << "\n";
        return;
      }
      // A run that succeeded but could not draw ends with the plot's error, in run.json as in the exit status.
      record->setExit(int(error.code()), error.what());
      record->write();
      throw;
    }
  };
  try {
    writeFrame(firstFrame, 0, secondsSince(runStart) * 1e3);
    // Each frame shows on a terminal; a log gets a line every few seconds.
    constexpr double progressAtOnceS = 0;
    std::optional<ProgressLine> progress;
    if (options.showProgress && writer) progress.emplace(stderr, progressAtOnceS);
    for (int frame = firstFrame + 1; frame <= frames; ++frame) {
      const auto frameStart = Clock::now();
      const int steps = simulation.advanceFrame(frame / scene.time.frameRateHz, log);
      summary.simulationWallS += secondsSince(frameStart);
      summary.steps += static_cast<std::uint64_t>(steps);
      writeFrame(frame, static_cast<std::uint64_t>(steps), secondsSince(frameStart) * 1e3);
      if (options.checkpointEvery > 0 && frame % options.checkpointEvery == 0) {
        const Checkpoint checkpoint = simulation.checkpoint(frame);  // over several processes, gathered by all
        if (writer) writeCheckpoint(options.outputDir / numberedFileName("checkpoint", frame, ".firn"), checkpoint);
      }
      summary.frames = frame;
      if (progress) {
        const double stepsPerS = double(summary.steps) / summary.simulationWallS;
        const double etaS = summary.simulationWallS / (frame - firstFrame) * (frames - frame);
        progress->show(progressText(frame, frames, simulation.timeS(), stepsPerS, etaS), frame == frames);
      }
    }
    progress.reset();
    if (options.passTimes) {
      log << "firn: time per pass (GPU: GL_TIME_ELAPSED; wall: dispatch to glFinish), mean over " << summary.steps << " steps:\n";
      logPassTimes(simulation.passTimes(), double(std::max<std::uint64_t>(summary.steps, 1)), log);
      if (snowSurface) {
        const int framesWritten = summary.frames - summary.firstFrame + 1;
        log << "firn: the surface's passes, mean over " << framesWritten << " frames:\n";
        logPassTimes(snowSurface->passTimes(), double(framesWritten), log);
      }
    }
    if (!options.videoPath.empty() && writer) {
      assembleVideo(options.outputDir, summary.frames + 1, scene.time.frameRateHz, options.videoPath);
      log << "firn: wrote " << options.videoPath.string() << "\n";
    }
  } catch (const Error& error) {
    finish(int(error.code()), error.what());
    throw;
  } catch (const std::exception& error) {
    finish(1, std::string("internal error: ") + error.what());
    throw;
  }
  finish(0, "");
  summary.wallS = secondsSince(runStart);
  return summary;
}

std::string checkHeadless(const Scene& scene, const RunOptions& options, std::ostream& log, DomainShare* share) {
  const int frames = options.frames.value_or(scene.time.frames);
  std::optional<Checkpoint> checkpoint;
  if (!options.resumePath.empty()) checkpoint = readCheckpoint(options.resumePath);
  gl::HeadlessContext context(options.gpuOrdinal);
  SimulationSession session(scene, context.info(), sessionOptionsFor(options, frames, share), log);
  // A checkpoint of another scene, or one that does not fit, is refused here as the run refuses it.
  if (checkpoint) session.simulation().resume(*checkpoint, options.resumePath);
  const int firstFrame = checkpoint ? checkpoint->frame : 0;
  const bool writer = share == nullptr || share->writesOutput();
  if (!writer) return "";
  // The pictures' renderer and the surface the pictures or caches would build, with the note a run gives when the
  // pictures fall back to particles.
  if (options.writesPictures()) {
    const render::OffscreenRenderer pictures(scene, options.imageSizePx);  // made and dropped: its programs compile
  }
  if ((options.writesPictures() && session.pictureRenderMode(options.renderMode) == render::RenderMode::Surface) ||
      options.writesSurfaceCaches()) {
    session.surface();
  }
  const int framesLeft = std::max(0, frames - firstFrame);
  const double frameS = 1.0 / scene.time.frameRateHz;
  // A fixed step: each frame takes ceil(frame / dt) equal steps (Scene.h).
  const std::string steps =
      scene.time.adaptive ? "adaptive steps of at most " + formatNumber(scene.time.dtS) + " s"
                          : withThousands(framesLeft * std::ceil(frameS / scene.time.dtS - 1e-9)) + " steps of " +
                                formatNumber(scene.time.dtS) + " s";
  return "firn: check: ready to run: " + withThousands(double(session.seeds().size())) + " particles, " +
         std::to_string(framesLeft) + " frames" + (checkpoint ? " from frame " + std::to_string(firstFrame) : "") +
         ", " + steps + ", scene fingerprint " + fingerprintHex(session.simulation().fingerprint()) +
         "; nothing simulated, nothing written";
}

}  // namespace firn
