// The `firn` command line (docs/command-line.md). Exit status: 0 success, 2 bad input,
// 3 unstable or overflowed simulation, 4 no usable OpenGL 4.3.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "Bench.h"
#include "Error.h"
#include "OptionChecks.h"
#include "Viewer.h"
#include "gl/Context.h"
#include "io/EnergyPlot.h"
#include "io/OutputPath.h"
#include "io/Ply.h"
#include "io/Text.h"
#include "io/Video.h"
#include "mpi/MpiShare.h"
#include "mpi/MpiWorld.h"
#include "run/Budget.h"
#include "run/HeadlessRun.h"
#include "run/Progress.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"
#include "voxelizer/ProcessMemory.h"
#include "voxelizer/Voxelizer.h"

namespace {

firn::Scene sceneOrDefault(const std::string& scenePath) {
  return scenePath.empty() ? firn::defaultScene() : firn::loadScene(scenePath);
}

// `firn run`, or with `checkOnly` its check (--check); under mpirun with several ranks, each rank's share of the
// domain (docs/distributed.md): rank 0 logs and writes, the others only simulate.
int runCommand(const std::string& scenePath, firn::RunOptions options, const firn::mpi::MpiWorld* world,
               int rebalanceEveryFrames, bool checkOnly) {
  const firn::Scene scene = sceneOrDefault(scenePath);
  std::optional<firn::mpi::MpiShare> share;
  std::ostream silent(nullptr);
  if (world != nullptr && world->size() > 1) {
    share.emplace(world->comm(), scene, rebalanceEveryFrames);
    options.gpuOrdinal = world->localRank();
  }
  const bool writer = !share || share->writesOutput();
  // Said before the run, not after an hour of simulation.
  if (!options.videoPath.empty() && !firn::findFfmpeg()) {
    throw firn::InputError("--mp4: the ffmpeg program is not on the PATH (Debian: apt-get install ffmpeg); "
                           "--png writes the frames without it");
  }
  if (!options.videoPath.empty()) firn::checkWritableFile(options.videoPath, "--mp4");
  if (options.writePlot && !firn::canPlot()) {
    throw firn::InputError("--plot: the gnuplot program is not on the PATH (Debian: apt-get install gnuplot-nox)");
  }
  options.showProgress = true;
  if (checkOnly) {
    const std::string ready =
        firn::checkHeadless(scene, options, writer ? std::cerr : silent, share ? &*share : nullptr);
    if (writer) std::printf("%s\n", ready.c_str());
    return 0;
  }
  const std::string outputDir = options.outputDir.string();
  const firn::RunSummary summary = firn::runHeadless(scene, options, writer ? std::cerr : silent,
                                                     share ? &*share : nullptr);
  const std::optional<firn::mpi::RunTraffic> traffic =
      share ? std::optional(share->summary()) : std::nullopt;  // every rank takes part
  if (!writer) return 0;
  if (traffic) {
    std::fprintf(stderr, "firn: %d processes, slabs of block layers across %s: %s\n", share->shares(),
                 share->slabs().describe().c_str(), traffic->describe().c_str());
  }
  std::printf("firn: wrote %d frames (%zu particles, %llu steps) to %s in %.1f s: %.2f ms per step on %s\n",
              summary.frames - summary.firstFrame + 1, summary.particles, static_cast<unsigned long long>(summary.steps),
              outputDir.c_str(), summary.wallS,
              summary.steps > 0 ? 1e3 * summary.simulationWallS / double(summary.steps) : 0.0, summary.renderer.c_str());
  return 0;
}

int viewCommand(const std::string& scenePath, firn::ViewOptions options) {
  // Said before the session, not when it ends.
  if (!options.screenshotPath.empty()) firn::checkWritableFile(options.screenshotPath, "--screenshot");
  if (!options.recordPath.empty()) firn::checkWritableFile(options.recordPath, "--record");
  // The editor edits a file, which it saves back.
  if (options.edit && scenePath.empty()) {
    throw firn::InputError("--edit: name the scene file to edit (firn view SCENE --edit)");
  }
  if (!options.edit && !scenePath.empty()) {
    const std::string missing = CLI::ExistingFile(scenePath);
    if (!missing.empty()) throw firn::InputError("scene: " + missing);
  }
  options.showProgress = true;
  // The editor begins a scene that does not exist yet from the built-in one (apps/firn/Viewer.cpp).
  const bool beginning = options.edit && !std::filesystem::exists(scenePath);
  firn::runViewer(beginning ? firn::defaultScene() : sceneOrDefault(scenePath), options);
  return 0;
}

struct VoxelizeOptions {
  std::string meshPath;
  std::string outputPath;
  double spacingM = 0;
  double cellSizeM = 0;
  double particlesPerCell = 8;
  std::string sampler = "lattice";
  std::uint32_t seed = 0x4669726e;
  firn::voxelizer::Transform placement;
  double densityKgPerM3 = 400;
  std::size_t maxParticles = 20000000;
};

// Host memory per particle of `firn voxelize`: the sampled positions (24 bytes, up to twice that while their
// vector grows), then the point cache (32) and the PLY's bytes (32) (docs/platform.md, Memory the driver reports).
constexpr double kVoxelizeBytesPerParticle = 112;

std::string formatG(double value) { return firn::format("%.3g", value); }

// Positions tested per particle the limits allow: a lattice over the mesh's box is tested point by point, and a
// mesh that fills little of its box (thin parts far apart) costs tests without particles. A sphere's box holds
// 1.9 lattice points per particle inside; 8 allows a shape that fills an eighth of its box.
constexpr double kVoxelizeTestsPerParticle = 8;

// N ∝ 1/s³: the spacing at which `count` becomes `most`, rounded up to 3 significant digits so that it does fit.
double fittingSpacingM(double spacingM, double count, double most) {
  const double fitting = spacingM * std::cbrt(count / most);
  const double unit = std::pow(10.0, std::floor(std::log10(fitting)) - 2);
  return std::ceil(fitting / unit) * unit;
}

// Refuses, before sampling, a fill estimated beyond --max-particles or the memory this process can allocate, or a
// lattice of more positions to test than kVoxelizeTestsPerParticle per particle those allow, with the spacing that
// would fit. Returns the most particles sampling may make.
std::size_t checkVoxelizeBudget(const VoxelizeOptions& options, const firn::voxelizer::TriangleMesh& mesh,
                                const firn::voxelizer::SampleEstimate& estimate, double spacingM) {
  const double allocatable = double(firn::voxelizer::allocatableBytes());
  const double memoryParticles = allocatable / kVoxelizeBytesPerParticle;
  const bool memoryBinds = memoryParticles < double(options.maxParticles);
  const double most = std::min(memoryParticles, double(options.maxParticles));
  const std::string limit = memoryBinds ? "the " + formatG(allocatable / double(1 << 30)) +
                                              " GiB this process can still allocate (about " +
                                              formatG(kVoxelizeBytesPerParticle) + " bytes per particle)"
                                        : "--max-particles " + firn::withThousands(double(options.maxParticles));
  const std::string raise = memoryBinds ? std::string() : ", or raise --max-particles";
  if (estimate.points > most) {
    throw firn::InputError(options.meshPath + ": about " + firn::withThousands(estimate.points) +
                           " particles at spacing " + formatG(spacingM) + " m (" +
                           firn::withThousands(estimate.insideTests) + " positions to test), more than " + limit +
                           "; a spacing of " + formatG(fittingSpacingM(spacingM, estimate.points, most)) +
                           " m or a smaller --scale would fit" + raise);
  }
  const double mostTests = kVoxelizeTestsPerParticle * most;
  if (estimate.insideTests > mostTests) {
    // The estimate's coarse lattice misses parts thinner than its spacing; the signed volume says what they hold.
    const firn::voxelizer::Bounds box = firn::voxelizer::bounds(mesh);
    const glm::dvec3 extentM = box.maxM - box.minM;
    const double volumeM3 = std::abs(firn::voxelizer::signedVolume(mesh));
    throw firn::InputError(
        options.meshPath + ": " + firn::withThousands(estimate.insideTests) + " positions to test at spacing " +
        formatG(spacingM) + " m over the mesh's " + formatG(extentM.x) + " × " + formatG(extentM.y) + " × " +
        formatG(extentM.z) + " m box, more than " + firn::withThousands(mostTests) + " (" +
        formatG(kVoxelizeTestsPerParticle) + " per particle that " + limit + " allows), for about " +
        firn::withThousands(std::max(estimate.points, volumeM3 / (spacingM * spacingM * spacingM))) +
        " particles (its signed volume is " + formatG(volumeM3) + " m³): the mesh fills little of its box. A spacing of " +
        formatG(fittingSpacingM(spacingM, estimate.insideTests, mostTests)) + " m or a smaller --scale would fit" +
        raise);
  }
  return static_cast<std::size_t>(most);
}

int voxelizeCommand(const VoxelizeOptions& options) {
  using Clock = std::chrono::steady_clock;
  namespace voxelizer = firn::voxelizer;
  const auto start = Clock::now();
  voxelizer::SamplingOptions sampling;
  // --spacing, or the spacing a body of particles_per_cell gets on a grid of cell_size (Sampling.cpp's rule).
  sampling.spacingM = options.spacingM > 0 ? options.spacingM : options.cellSizeM / std::cbrt(options.particlesPerCell);
  sampling.sampler = options.sampler == "poisson_disk" ? voxelizer::Sampler::PoissonDisk : voxelizer::Sampler::Lattice;
  sampling.seed = options.seed;
  voxelizer::TriangleMesh mesh;
  // The voxelizer knows no exit statuses; a bad mesh file is bad input.
  try {
    mesh = voxelizer::transformed(voxelizer::loadMesh(options.meshPath), options.placement);
  } catch (const voxelizer::MeshError& error) {
    throw firn::InputError(error.what());
  }
  const voxelizer::MeshSurface surface = voxelizer::measureSurface(mesh);
  const std::string problem = voxelizer::whyNotFillable(mesh, surface, sampling.spacingM);
  if (!problem.empty()) throw firn::InputError(options.meshPath + ": " + problem);
  const auto loaded = Clock::now();

  const voxelizer::SampleEstimate estimate = voxelizer::estimateVoxelize(mesh, sampling);
  sampling.maxPoints = checkVoxelizeBudget(options, mesh, estimate, sampling.spacingM);
  std::fprintf(stderr, "firn voxelize: about %s particles to sample (%s positions to test)\n",
               firn::withThousands(estimate.points).c_str(), firn::withThousands(estimate.insideTests).c_str());
  std::optional<firn::ProgressLine> progressLine(std::in_place, stderr);
  sampling.progress = [&](double fraction) { progressLine->showFraction("firn voxelize: sampling", fraction); };
  const auto sample = [&](const voxelizer::SamplingOptions& with) {
    try {
      return voxelizer::voxelize(mesh, with);
    } catch (const voxelizer::TooManySamples& tooMany) {
      throw firn::InputError(options.meshPath + ": sampling stopped past " + firn::withThousands(double(tooMany.maxPoints())) +
                             " particles, the most --max-particles and this process's memory allow (the estimate "
                             "before sampling was " + firn::withThousands(estimate.points) + "); use a coarser spacing");
    }
  };
  std::vector<glm::dvec3> positions = sample(sampling);
  progressLine.reset();
  const auto sampled = Clock::now();
  if (positions.empty()) {
    throw firn::InputError(options.meshPath + ": " + voxelizer::whyNoParticles(mesh, surface, sampling.spacingM));
  }
  sampling.progress = nullptr;
  // Each particle carries its share of the volume the samples fill (voxelizer/Samplers.h).
  const double volumePerParticleM3 = voxelizer::volumePerSampleM3(positions.size(), sampling, sample);
  const double volumeM3 = volumePerParticleM3 * double(positions.size());
  const std::string sheet = voxelizer::sheetWarning(surface, positions.size(), sampling.spacingM);
  if (!sheet.empty()) std::fprintf(stderr, "firn voxelize: warning: %s: %s\n", options.meshPath.c_str(), sheet.c_str());
  const auto massKg = float(options.densityKgPerM3 * volumePerParticleM3);
  const std::size_t particleCount = positions.size();
  firn::PointCache cloud;
  cloud.positionsM.assign(positions.begin(), positions.end());
  std::vector<glm::dvec3>().swap(positions);  // freed before the PLY's bytes are made
  cloud.velocitiesMPerS.assign(particleCount, glm::vec3(0.0f));
  cloud.massesKg.assign(particleCount, massKg);
  cloud.plasticJ.assign(particleCount, 1.0f);
  firn::writePly(options.outputPath, cloud);
  const voxelizer::Bounds box = voxelizer::bounds(mesh);
  const auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
  std::printf("firn voxelize: %zu triangles, bounds [%.4g, %.4g, %.4g] to [%.4g, %.4g, %.4g] m\n",
              mesh.triangles.size(), box.minM.x, box.minM.y, box.minM.z, box.maxM.x, box.maxM.y, box.maxM.z);
  const std::string meshVolume =
      surface.open() ? "the mesh is open, " + std::to_string(surface.boundaryEdges) +
                           " edges bordering holes, so it has no exact volume; its signed volume about its centre is " +
                           formatG(voxelizer::signedVolume(mesh)) + " m³"
                     : "the mesh's signed volume is " + formatG(voxelizer::signedVolume(mesh)) + " m³";
  std::printf("firn voxelize: %zu particles at spacing %.4g m (%s): volume %.6g m³ (%s)\n", particleCount,
              sampling.spacingM, options.sampler.c_str(), volumeM3, meshVolume.c_str());
  std::printf("firn voxelize: wrote %s in %.2f s (load %.2f s, sample %.2f s)\n", options.outputPath.c_str(),
              seconds(Clock::now() - start), seconds(loaded - start), seconds(sampled - loaded));
  return 0;
}

struct BenchCommand {
  firn::bench::BenchOptions options;
  std::string outputDir;
  std::string assetsDir;
  std::string thesisCloud;
  std::string plotsOnly;
  bool quick = false;
  bool tiny = false;
  bool noPlots = false;
};

int benchCommand(BenchCommand command) {
  if (!command.plotsOnly.empty()) {
    if (!std::filesystem::is_directory(command.plotsOnly)) {
      throw firn::InputError("--plots-only: " + command.plotsOnly + ": no such folder");
    }
    return firn::bench::makePlots(command.plotsOnly, std::cerr) ? 0 : static_cast<int>(firn::ExitCode::BadInput);
  }
  firn::bench::BenchOptions& options = command.options;
  options.size = command.tiny    ? firn::bench::BenchSize::Tiny
                 : command.quick ? firn::bench::BenchSize::Quick
                                 : firn::bench::BenchSize::Default;
  options.outputDir = command.outputDir;
  options.assetsDir = command.assetsDir;
  options.thesisCloud = command.thesisCloud;
  const std::string summary = firn::bench::runBench(options, std::cerr);
  if (!command.noPlots) firn::bench::makePlots(options.outputDir, std::cerr);
  std::printf("%s", summary.c_str());
  return 0;
}

int infoCommand() {
  firn::gl::HeadlessContext context;
  const firn::gl::ContextInfo& info = context.info();
  std::printf("platform  %s\nvendor    %s\nrenderer  %s\nversion   %s\nfloat atomics (GL_NV_shader_atomic_float)  %s\n"
              "max shader storage block  %lld MiB\n",
              info.platform.c_str(), info.vendor.c_str(), info.renderer.c_str(), info.version.c_str(),
              info.hasFloatAtomics ? "yes" : "no", info.maxStorageBlockBytes / (1024 * 1024));
  // P2G's shape on this device, timed as a run times it, on the built-in scene (sim/TransferShape.h).
  const firn::Scene scene = firn::defaultScene();
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  const firn::Simulation simulation(scene, seeds, info);
  std::printf("transfers (the built-in scene, %zu particles)  %s\n", seeds.size(),
              simulation.transferShapeChoice()->describe().c_str());
  return 0;
}

}  // namespace

// An error, said once: under mpirun by the rank it happened on, bad input (the same on every rank) by rank 0 alone,
// and a run another rank stopped not at all (that rank says why). Returns the exit status.
int reportError(const firn::Error& error, const firn::mpi::MpiWorld* world) {
  if (world == nullptr || world->size() == 1) {
    std::fprintf(stderr, "\nfirn: error: %s\n", error.what());
    return static_cast<int>(error.code());
  }
  if (dynamic_cast<const firn::StoppedElsewhere*>(&error) != nullptr) {
    // The rank that failed ends the run (MPI_Abort) once it has said why; this one waits for that.
    std::this_thread::sleep_for(std::chrono::seconds(10));
    return static_cast<int>(error.code());
  }
  const bool sameEverywhere = dynamic_cast<const firn::InputError*>(&error) != nullptr;
  if (!sameEverywhere || world->rank() == 0) {
    std::fprintf(stderr, "\nfirn: error (rank %d of %d): %s\n", world->rank(), world->size(), error.what());
  }
  return static_cast<int>(error.code());
}

int firnMain(int argc, char** argv, const firn::mpi::MpiWorld* world) {
  CLI::App app{"Firn: a GPU snow engine (Material Point Method, Stomakhin et al. 2013) on OpenGL 4.3 compute shaders"};
  app.require_subcommand(1);

  const std::map<std::string, firn::render::ColorMode> colorModes = {
      {"material", firn::render::ColorMode::Material},
      {"speed", firn::render::ColorMode::Speed},
      {"plastic", firn::render::ColorMode::PlasticCompression},
      {"stress", firn::render::ColorMode::Stress}};
  const char* colorHelp = "Particle colour: material, speed, plastic (compression J_P) or stress";
  const std::map<std::string, firn::render::RenderMode> renderModes = {
      {"particles", firn::render::RenderMode::Particles}, {"surface", firn::render::RenderMode::Surface}};
  const char* renderHelp =
      "Draw the snow as its surface (rebuilt each frame on the GPU) or as its particles; by default the surface, or "
      "the particles with a note when the scene's surface settings do not suit them";
  const char* domainBoxHelp = "Outline the simulation domain's box";
  firn::render::RenderMode runRenderMode = firn::render::RenderMode::Surface;
  firn::render::RenderMode viewRenderMode = firn::render::RenderMode::Surface;
  const char* sceneHelp = "Scene file (JSON); without it, the built-in snowball-at-a-wall scene";

  std::string scenePath;
  firn::RunOptions runOptions;
  std::string outputDir = runOptions.outputDir.string();
  std::string videoPath;
  bool noPly = false;
  bool checkOnly = false;
  CLI::App* run = app.add_subcommand(
      "run", "Simulate a scene headless (EGL) and write stats.csv, run.json and PLY frames, bodies.csv where objects "
             "move, and if asked pictures, surface and object meshes, VDB caches and the energy budget's plot");
  run->add_option("scene", scenePath, sceneHelp)->check(CLI::ExistingFile);
  run->add_option("--frames", runOptions.frames, "Number of frames after frame 0 (default: the scene's time.frames)")
      ->check(firn::cli::inRange(0, 1000000));
  run->add_option("--out", outputDir, "Output folder for stats.csv and frame_NNNN.ply")->capture_default_str();
  run->add_flag("--no-ply", noPly, "Write stats.csv (and bodies.csv) only, no point caches");
  run->add_flag("--check", checkOnly,
                "Do what the run does before its first step (load, particle budget, sampling, distance fields, "
                "pre-flight, the GPU's buffers and programs) and print pre-flight's report; simulate and write nothing "
                "(the output folder is not looked at). Exit 0 when the scene would run, 2 (bad input) or 4 (no usable "
                "OpenGL) as the run would");
  run->add_flag("--pass-times", runOptions.passTimes,
                "Time each GPU pass (GL_TIME_ELAPSED) and print the means; slows the run");
  run->add_flag("--png", runOptions.writePng, "Also render each frame offscreen to frame_NNNN.png");
  run->add_option("--width", runOptions.imageSizePx.x, "Picture width in pixels (--png, --mp4)")
      ->check(firn::cli::inRange(16, 8192))->capture_default_str();
  run->add_option("--height", runOptions.imageSizePx.y, "Picture height in pixels (--png, --mp4)")
      ->check(firn::cli::inRange(16, 8192))->capture_default_str();
  run->add_option("--color", runOptions.colorMode, colorHelp)
      ->transform(firn::cli::oneOf(colorModes))
      ->default_str("material");
  CLI::Option* runRender = run->add_option("--render", runRenderMode, renderHelp)
      ->transform(firn::cli::oneOf(renderModes))
      ->default_str("surface");
  run->add_flag("--domain-box", runOptions.domainBox, domainBoxHelp);
  run->add_flag("--mesh", runOptions.writeMesh,
                "Also write the snow's surface as frame_NNNN_surface.ply (binary PLY: vertices with normals, triangles) "
                "and each rigid body and moving collider posed as OBJECT_NNNN.ply (colliders_1_0000.ply)");
  run->add_flag("--vdb", runOptions.writeVdb,
                "Also write frame_NNNN.vdb (OpenVDB): a density grid and a level set of the snow's surface");
  run->add_option("--mp4", videoPath, "Render the frames (as --png) and assemble them into this video with ffmpeg");
  run->add_flag("--plot", runOptions.writePlot,
                "Also draw energy.png, the energy budget over time as stacked areas, with gnuplot (and energy.gp)");
  run->add_option("--checkpoint-every", runOptions.checkpointEvery,
                  "Write checkpoint_NNNN.firn (the complete state) every K frames")
      ->check(firn::cli::inRange(1, 1000000));
  std::string resumePath;
  run->add_option("--resume", resumePath, "Continue from a checkpoint of this scene, bit for bit as if never interrupted")
      ->check(CLI::ExistingFile);
  const std::string transferShapeHelp =
      "Time only these shapes of the transfers (P2G, and a semi-implicit scene's Hessian product) before keeping the "
      "fastest: tiles, blocks (each group size), blocks-64, blocks-128 or blocks-256 (default: every shape the scene "
      "can take). They write the same bytes; for benchmarks and tests";
  run->add_option("--transfer-shape", runOptions.transferShapes, transferShapeHelp)
      ->transform(firn::cli::oneOf(firn::transferShapeNames()));
  int rebalanceEveryFrames = 10;
  run->add_option("--rebalance-every", rebalanceEveryFrames,
                  "Under mpirun: redraw the ranks' slabs for their particle counts every K frames (0: never)")
      ->check(firn::cli::inRange(0, 1000000))->capture_default_str();

  firn::ViewOptions viewOptions;
  std::string screenshotPath;
  CLI::App* view = app.add_subcommand("view", "Open a window and watch the scene (GLFW; needs a display or xvfb-run)");
  // A file that does not exist is one to begin with the editor (--edit); without it, an error as `firn run`'s.
  view->add_option("scene", scenePath, sceneHelp);
  view->add_option("--frames", viewOptions.frames, "Exit after this many drawn frames")->check(firn::cli::inRange(1, 100000000));
  view->add_option("--screenshot", screenshotPath, "With --frames: write the last frame to this PNG file")
      ->needs("--frames");
  view->add_option("--width", viewOptions.widthPx, "Window width in pixels")->check(firn::cli::inRange(16, 8192))
      ->capture_default_str();
  view->add_option("--height", viewOptions.heightPx, "Window height in pixels")->check(firn::cli::inRange(16, 8192))
      ->capture_default_str();
  view->add_option("--throw-at", viewOptions.throwAtFrames,
                   "Throw a snowball from the camera at these frames (comma-separated), as the T key does (scripted demos)")
      ->check(firn::cli::inRange(1, 100000000))->delimiter(',');
  view->add_option("--color", viewOptions.colorMode, colorHelp)
      ->transform(firn::cli::oneOf(colorModes))
      ->default_str("material");
  view->add_option("--transfer-shape", viewOptions.transferShapes, transferShapeHelp)
      ->transform(firn::cli::oneOf(firn::transferShapeNames()));
  CLI::Option* viewRender = view->add_option("--render", viewRenderMode, renderHelp)
      ->transform(firn::cli::oneOf(renderModes))
      ->default_str("surface");
  view->add_flag("--domain-box", viewOptions.domainBox, domainBoxHelp);
  CLI::Option* edit = view->add_flag("--edit", viewOptions.edit,
                                     "Open the scene editor: a panel that edits, checks and saves SCENE, which stays "
                                     "at its start until run (Tab switches between editing and running)");
  std::string replayPath, recordPath;
  view->add_option("--replay", replayPath, "With --edit: replay the editor's input from this JSON file (tests, demos)")
      ->check(CLI::ExistingFile)->needs(edit);
  view->add_option("--record", recordPath, "With --edit: write the editor's input to this JSON file for --replay")
      ->needs(edit);

  VoxelizeOptions voxelizeOptions;
  std::vector<double> rotateDeg, translateM;
  CLI::App* voxelize = app.add_subcommand("voxelize", "Fill a mesh (OBJ, PLY, STL, glTF …) with particles and write a PLY");
  voxelize->add_option("mesh", voxelizeOptions.meshPath, "Mesh file (anything assimp reads)")->required()
      ->check(CLI::ExistingFile);
  voxelize->add_option("--out", voxelizeOptions.outputPath, "Output point cloud (binary PLY: x y z vx vy vz mass plastic_j)")
      ->required();
  CLI::Option* spacing = voxelize->add_option("--spacing", voxelizeOptions.spacingM, "Particle spacing s in metres")
                             ->check(firn::cli::positive());
  CLI::Option* cellSize = voxelize->add_option("--cell-size", voxelizeOptions.cellSizeM,
                                               "Grid cell size h in metres: spacing h / cbrt(--particles-per-cell)")
                              ->check(firn::cli::positive())->excludes(spacing);
  voxelize->add_option("--particles-per-cell", voxelizeOptions.particlesPerCell, "Particles per grid cell (with --cell-size)")
      ->check(firn::cli::inRange(0.001, 1000))->needs(cellSize)->capture_default_str();
  voxelize->add_option("--sampler", voxelizeOptions.sampler, "lattice (jittered, grid-aligned) or poisson_disk (blue noise)")
      ->check(firn::cli::oneOf(std::vector<std::string>{"lattice", "poisson_disk"}))->capture_default_str();
  voxelize->add_option("--seed", voxelizeOptions.seed, "Random seed of the jitter or the Poisson-disk samples");
  voxelize->add_option("--scale", voxelizeOptions.placement.scale, "Uniform scale applied to the mesh first")
      ->check(firn::cli::positive())->capture_default_str();
  voxelize->add_option("--rotate-deg", rotateDeg, "Rotation X,Y,Z in degrees (about x, then y, then z), after scaling")
      ->expected(3)->delimiter(',');
  voxelize->add_option("--translate", translateM, "Translation X,Y,Z in metres, applied last")->expected(3)->delimiter(',');
  voxelize->add_option("--density", voxelizeOptions.densityKgPerM3, "Density in kg/m³ of the particles' masses (density · s³ on the lattice)")
      ->check(firn::cli::positive())->capture_default_str();
  voxelize->add_option("--max-particles", voxelizeOptions.maxParticles,
                       "Refuse, before sampling, a mesh estimated to yield more particles than this")
      ->check(firn::cli::inRange(1, 2147483647))->capture_default_str();

  BenchCommand benchOptions;
  benchOptions.outputDir = benchOptions.options.outputDir.string();
  benchOptions.assetsDir = firn::bench::defaultAssetsDir().string();
  CLI::App* bench = app.add_subcommand(
      "bench", "Measure time per step against particles and grid size, per-pass times, P2G with fixed, float and "
               "no atomics, and the speed/accuracy trade; write CSV tables and their plots (benchmarks/README.md)");
  CLI::Option* quick = bench->add_flag(
      "--quick", benchOptions.quick, "Sizes for a CPU renderer (llvmpipe on 2 cores: under 3 minutes), every table's shape "
                                     "with fewer and smaller points; the default sizes are for GPUs, up to millions of "
                                     "particles");
  bench->add_flag("--tiny", benchOptions.tiny, "For tests: the smallest sizes, which check the machinery and measure nothing")
      ->excludes(quick);
  bench->add_option("--out", benchOptions.outputDir, "Output folder for the tables, machine.txt, summary.txt and plots")
      ->capture_default_str();
  bench->add_option("--repeats", benchOptions.options.repeats,
                    "Timed runs per configuration, each table giving their median (default: the sizes' own, 3 quick, "
                    "5 otherwise)")
      ->check(firn::cli::inRange(1, 1000));
  bench->add_option("--steps", benchOptions.options.stepsPerRepeat, "Steps per timed run (default: the sizes' own)")
      ->check(firn::cli::inRange(1, 1000000));
  bench->add_option("--only", benchOptions.options.tables, "Only these tables (comma-separated)")
      ->check(firn::cli::oneOf(firn::bench::tableNames()))->delimiter(',');
  bench->add_option("--assets", benchOptions.assetsDir, "Firn's assets folder (scenes/bunny_thesis.json, meshes/bunny.obj)")
      ->capture_default_str();
  bench->add_option("--thesis-cloud", benchOptions.thesisCloud,
                    "The thesis implementation's bunny, a point cloud (x,y,z per line): adds thesis.csv, the same scene in "
                    "Firn against the thesis's 546 ms per step")
      ->check(CLI::ExistingFile);
  bench->add_option("--thesis-dt", benchOptions.options.thesisDtS,
                    "Time step of thesis.csv in seconds (the thesis's 1e-3 is beyond Firn's explicit elastic bound)")
      ->check(firn::cli::positive())->capture_default_str();
  bench->add_option("--atomics", benchOptions.options.atomics,
                    "How P2G sums in the particle, grid, passes and thesis tables, a series each (comma-separated: "
                    "fixed, float); default: fixed, and float where the driver has float atomics")
      ->check(firn::cli::oneOf(std::vector<std::string>{"fixed", "float"}))->delimiter(',');
  bench->add_flag("--no-plots", benchOptions.noPlots, "Write the tables only");
  bench->add_option("--plots-only", benchOptions.plotsOnly, "Measure nothing: plot the tables already in this folder");

  app.add_subcommand("info", "Show the OpenGL context Firn gets (set FIRN_EGL_DEVICE=N to pick an EGL device)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help is a parse "error" that succeeds: CLI11 prints the help. Anything else is bad input, said as Firn's
    // other errors are.
    if (error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(error);
    if (world == nullptr || world->rank() == 0) {  // the same on every rank
      std::fprintf(stderr, "firn: error: %s\nRun with --help for more information.\n", error.what());
    }
    return static_cast<int>(firn::ExitCode::BadInput);
  }
  // Read until the transfer shape became an option: a script that still sets it would time every shape unawares.
  const char* oldShape = std::getenv("FIRN_TRANSFER_SHAPE");
  if (oldShape != nullptr && (world == nullptr || world->rank() == 0)) {
    std::fprintf(stderr, "firn: warning: FIRN_TRANSFER_SHAPE is no longer read; use --transfer-shape %s\n", oldShape);
  }

  try {
    if (world != nullptr && world->size() > 1 && !run->parsed()) {
      throw firn::InputError("under mpirun only `firn run` runs over several processes; start other commands without "
                             "it");
    }
    if (run->parsed()) {
      runOptions.outputDir = outputDir;
      runOptions.writePly = !noPly;
      runOptions.videoPath = videoPath;
      runOptions.resumePath = resumePath;
      runOptions.commandLine.assign(argv, argv + argc);
      if (runRender->count() > 0) runOptions.renderMode = runRenderMode;
      return runCommand(scenePath, runOptions, world, rebalanceEveryFrames, checkOnly);
    }
    if (view->parsed()) {
      viewOptions.screenshotPath = screenshotPath;
      viewOptions.scenePath = scenePath;
      viewOptions.replayPath = replayPath;
      viewOptions.recordPath = recordPath;
      if (viewRender->count() > 0) viewOptions.renderMode = viewRenderMode;
      return viewCommand(scenePath, viewOptions);
    }
    if (voxelize->parsed()) {
      if (spacing->count() == 0 && cellSize->count() == 0) {
        throw firn::InputError("voxelize: give --spacing S, or --cell-size H (with --particles-per-cell N)");
      }
      if (rotateDeg.size() == 3) voxelizeOptions.placement.rotateDeg = {rotateDeg[0], rotateDeg[1], rotateDeg[2]};
      if (translateM.size() == 3) voxelizeOptions.placement.translateM = {translateM[0], translateM[1], translateM[2]};
      return voxelizeCommand(voxelizeOptions);
    }
    if (bench->parsed()) return benchCommand(benchOptions);
    return infoCommand();
  } catch (const firn::Error& error) {
    return reportError(error, world);
  } catch (const std::exception& error) {
    if (world != nullptr && world->size() > 1) {
      std::fprintf(stderr, "\nfirn: internal error (rank %d of %d): %s\n", world->rank(), world->size(), error.what());
    } else {
      std::fprintf(stderr, "\nfirn: internal error: %s\n", error.what());
    }
    return 1;
  }
}

int main(int argc, char** argv) {
  if (!firn::mpi::launchedByMpi()) return firnMain(argc, argv, nullptr);
  // Started by mpirun: MPI first, before the GL context (mpi/MpiWorld.h). A rank that fails ends them all, so that
  // none waits for it in an exchange.
  firn::mpi::MpiWorld world(argc, argv);
  const int status = firnMain(argc, argv, &world);
  if (status != 0 && world.size() > 1) world.abort(status);
  return status;
}
