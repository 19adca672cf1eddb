#pragma once
// The scene description: what the JSON scene file (docs/scene-format.md) says, parsed and validated, in SI units.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace firn {
namespace voxelizer {
struct TriangleMesh;
}

enum class Kernel { Quadratic, Cubic };          // B-spline order: 27 or 64 nodes per particle
enum class Transfer { PicFlip, Apic };            // Snow thesis 2015's PIC/FLIP blend, or Blažević 2022's APIC
// How P2G sums: fixed-point integers (exact, bitwise deterministic), or floats with NV float atomics.
enum class Atomics { FixedPoint, Float };
enum class Boundary { Sticky, Slip, Separate };   // Blažević 2022 ch. 5
// Where the particles' initial volumes V0 come from: the grid density after a first P2G of mass, V0 = m / ρ_grid
// (Stomakhin 2013 §6 step 2; too large near free surfaces, where the kernel reads the density low), or the
// material's density, V0 = m / ρ (exact where the body is filled at that density, as sampled bodies are).
enum class ParticleVolume { GridDensity, MaterialDensity };
// How the grid velocities of a step are found: explicitly (v* alone: Δt below the elastic bound h / c), or
// semi-implicitly (Stomakhin 2013 §6, eq. 9: (I + β Δt² M⁻¹ H) v = v*, steps bounded by the particles' CFL alone).
enum class Integrator { Explicit, SemiImplicit };
enum class BodyShape { Sphere, Box, Mesh, Points };
enum class BodySampler { Lattice, PoissonDisk };  // how sphere, box and mesh bodies are filled
enum class ColliderShape { Plane, Sphere, Box, Mesh };
enum class RigidShape { Sphere, Box, Mesh };

struct GridSpec {
  glm::dvec3 originM{0.0};
  glm::ivec3 cells{64};  // nodes per axis = cells + 1
  double cellSizeM = 0.02;

  // The outer cells on every side are walls (docs/algorithm.md); particles start in the interior between them.
  static constexpr int wallCells = 2;
  glm::dvec3 interiorMinM() const { return originM + double(wallCells) * cellSizeM; }
  glm::dvec3 interiorMaxM() const { return originM + glm::dvec3(cells - wallCells) * cellSizeM; }

  // The spacing of 32-bit floats at the domain's corner farthest from (0, 0, 0): the GPU keeps positions as floats,
  // so no particle's position there is finer than this. A step moves a particle by whole multiples of it: one
  // slower than half of it per step stands still, and the B-spline weights see where in its cell it is only to
  // this resolution.
  double positionResolutionM() const;
  // Coarser than a hundredth of a cell is refused: the weights would know fewer than 100 places per cell, and a
  // particle slower than half a percent of a cell per step would never move. Coarser than a thousandth is a
  // warning (pre-flight gives the speed below which particles stand still). At the origin a grid of 1024 cells
  // reaches h / 8192 at its far corner, within both.
  static constexpr double refusedPositionResolutionCells = 1.0 / 100;
  static constexpr double warnedPositionResolutionCells = 1.0 / 1000;
};

struct TimeSpec {
  double dtS = 1e-4;        // fixed: each frame takes ceil(frame duration / dt) equal steps; adaptive: the largest step
  bool adaptive = false;    // each step as large as the CFL and elastic bounds allow, times `cfl`
  double cfl = 0.4;         // the fraction of a cell the fastest particle, or the elastic wave, may cross per step
  double frameRateHz = 30;  // frame N is the state at N / frameRateHz
  int frames = 60;

  // A frame may take at most this many steps (time.dt against frame_rate): at a millisecond per step, a GPU's
  // cost for a modest scene, that is a quarter of an hour per frame; more is a unit mistake. SteppingPolicy counts
  // a frame's steps in an int.
  static constexpr double maxStepsPerFrame = 1e6;
};

struct SolverSpec {
  Kernel kernel = Kernel::Cubic;
  Transfer transfer = Transfer::PicFlip;
  double flipRatio = 0.95;  // α in v = α v_FLIP + (1 − α) v_PIC
  Atomics atomics = Atomics::FixedPoint;
  ParticleVolume particleVolume = ParticleVolume::GridDensity;
  Integrator integrator = Integrator::Explicit;
  // Semi-implicit only: β (0 explicit, 1 backward Euler), the relative residual ‖r‖ / ‖M v*‖ (in the P⁻¹ norm, P the preconditioner) at
  // which the solve stops, and the most conjugate residual iterations it takes.
  double implicitRatio = 1;
  double tolerance = 1e-4;
  int maxIterations = 100;
  static constexpr int maxIterationsAllowed = 1000;  // the GPU's registers (gpu_contract.h SOLVER_MAX_ITERATIONS)

  bool semiImplicit() const { return integrator == Integrator::SemiImplicit; }
};

// The material families of the source theses (docs/scene-format.md's table of models and keys).
enum class MaterialModel {
  Snow,            // Stomakhin et al. 2013: fixed corotated elasticity, plastic clamping and hardening
  FixedCorotated,  // Blažević 2022 §4.2.2: Ψ = μ‖F − R‖² + λ/2 (J − 1)²
  NeoHookean,      // Blažević 2022 §4.2.1: Ψ = μ/2 (tr FᵀF − 3) − μ ln J + λ/2 ln² J
  Water,           // Blažević 2022 §4.1: Ψ(J) = −k (J^{1−γ}/(1−γ) − J), optionally viscous
  DruckerPrager,   // Blažević 2022 §4.4, Klár et al. 2016: sand, Hencky elasticity with a friction cone
};

struct Material {
  std::string name;
  // Elastic solids, snow and sand:
  double youngsModulusPa = 1.4e5;
  double poissonRatio = 0.2;
  double densityKgPerM3 = 400;
  // Snow:
  double criticalCompression = 2.5e-2;  // θc
  double criticalStretch = 7.5e-3;      // θs
  double hardening = 10;                // ξ
  MaterialModel model = MaterialModel::Snow;
  // Water: pressure p = k (J^−γ − 1), and the dynamic viscosity of its optional viscous stress.
  double bulkModulusPa = 0;
  double gamma = 7;
  double viscosityPaS = 0;
  // Sand: the friction angle φ = h0 + (h1 q − h3) e^{−h2 q} of the hardening state q (Klár 2016 eq. 29, Blažević
  // 2022 eq. 4.17); without hardening, φ = friction_angle_deg throughout (h0 = φ, h1 = h2 = h3 = 0).
  double hardeningH0Deg = 30;
  double hardeningH1Deg = 0;
  double hardeningH2 = 0;
  double hardeningH3Deg = 0;

  bool needsDeformationGradient() const { return model != MaterialModel::Water; }
  // Whether the semi-implicit step can take it: the Hessian of its energy is implemented for the elastic models
  // (snow's with its plasticity held for the step), not for water or sand.
  bool hasHessian() const {
    return model == MaterialModel::Snow || model == MaterialModel::FixedCorotated || model == MaterialModel::NeoHookean;
  }
};

// The model's name in scene files.
const char* modelName(MaterialModel model);

struct Body {
  BodyShape shape = BodyShape::Sphere;
  glm::dvec3 centerM{0.0};  // sphere
  double radiusM = 0;       // sphere
  glm::dvec3 minM{0.0};     // box
  glm::dvec3 maxM{0.0};     // box
  int materialIndex = 0;    // into Scene::materials
  glm::dvec3 velocityMPerS{0.0};
  glm::dvec3 angularVelocityRadPerS{0.0};  // about the body's centre of mass: v = v0 + ω × (x − c)
  // Blažević 2022's modifiers of the material for this body alone: λ0, μ0 and the particle masses are scaled.
  double lambdaScale = 1;
  double muScale = 1;
  double massScale = 1;
  // An emitter releases its particles over [start_frame, start_frame + duration_frames) frames, leading edge
  // first; the particle buffers reserve room for them from the start.
  int startFrame = 0;
  int durationFrames = 0;
  bool isEmitter() const { return startFrame > 0 || durationFrames > 0; }
  // Sphere, box and mesh bodies are sampled at spacing cell_size / cbrt(particlesPerCell); for a points body
  // it is (cell_size / the cloud's spacing)³, what the fixed-point bounds need to know.
  double particlesPerCell = 8;
  BodySampler sampler = BodySampler::Lattice;

  // Mesh and points bodies: the file (as the scene names it, and resolved against the scene's folder), and
  // the placement applied to it: p' = translate + R · (scale · p), R = Rz · Ry · Rx (voxelizer/Mesh.h).
  std::string path;
  std::filesystem::path resolvedPath;
  double scale = 1;
  glm::dvec3 rotateDeg{0.0};
  glm::dvec3 translateM{0.0};
  // Loaded and placed by the scene loader, so that a bad file is reported with the scene, before any run.
  std::shared_ptr<const voxelizer::TriangleMesh> mesh;
  std::shared_ptr<const std::vector<glm::dvec3>> pointsM;
  // Points bodies: kilograms per particle, from "particle_mass", the file's own masses, or ρ s³ with s the
  // cloud's median neighbour spacing (in that order of preference).
  std::vector<double> pointMassesKg;  // one per point, or a single value for all
  double pointSpacingM = 0;
  glm::dvec3 loadedMinM{0.0}, loadedMaxM{0.0};  // mesh and points: bounds after placement

  glm::dvec3 boundsMinM() const {
    switch (shape) {
      case BodyShape::Sphere: return centerM - radiusM;
      case BodyShape::Box: return minM;
      default: return loadedMinM;
    }
  }
  glm::dvec3 boundsMaxM() const {
    switch (shape) {
      case BodyShape::Sphere: return centerM + radiusM;
      case BodyShape::Box: return maxM;
      default: return loadedMaxM;
    }
  }
};

// One keyframe of a collider's motion: at `timeS` the collider is its shape at rest turned by `rotateDeg` about
// its pivot (R = R_z R_y R_x, as bodies' rotate_deg) and moved by `translateM` (docs/algorithm.md, Colliders).
struct ColliderKeyframe {
  double timeS = 0;
  glm::dvec3 translateM{0.0};
  glm::dvec3 rotateDeg{0.0};
};

struct Collider {
  ColliderShape shape = ColliderShape::Plane;
  glm::dvec3 pointM{0.0};   // plane: a point on it
  glm::dvec3 normal{0, 1, 0};  // plane: unit normal pointing out of the solid
  glm::dvec3 centerM{0.0};  // sphere
  double radiusM = 0;       // sphere
  glm::dvec3 minM{0.0};     // box
  glm::dvec3 maxM{0.0};     // box
  glm::dvec3 velocityMPerS{0.0};  // without keyframes, the collider translates at this velocity
  glm::dvec3 pivotM{0.0};         // the point it turns about, at rest (the shape's centre unless given)
  std::vector<ColliderKeyframe> keyframes;  // its poses at increasing times; empty: it moves at velocityMPerS
  double friction = 0;            // Coulomb μ
  Boundary boundary = Boundary::Slip;
  // Mesh colliders: the file (as the scene names it, and resolved against the scene's folder); the mesh placed at
  // rest as mesh bodies are (p' = translate + R · (scale · p)), loaded with the scene; and the samples of its signed
  // distance field per grid cell and axis (spacing cell_size / fieldResolution).
  std::string path;
  std::filesystem::path resolvedPath;
  std::shared_ptr<const voxelizer::TriangleMesh> mesh;
  double fieldResolution = 2;
};

// A rigid body the snow pushes and that pushes the snow (docs/algorithm.md, Rigid bodies). Its frame has its origin
// at the centre of mass and its axes at the shape's own (a box's edges; a mesh's file axes after the placement's
// rotation, so a mesh body starts unturned); it starts turned by `rotateDeg` (boxes) and moves under gravity, the
// snow's impulses and its contacts with the colliders and the domain walls.
struct RigidBody {
  RigidShape shape = RigidShape::Sphere;
  glm::dvec3 centerM{0.0};      // sphere and box: the centre at t = 0
  double radiusM = 0;           // sphere
  glm::dvec3 halfExtentsM{0.0}; // box, along its own axes
  glm::dvec3 rotateDeg{0.0};    // box: its turn at t = 0 (R = R_z R_y R_x)
  // Mesh: the file, and the mesh placed as mesh colliders' are, in world coordinates at t = 0.
  std::string path;
  std::filesystem::path resolvedPath;
  std::shared_ptr<const voxelizer::TriangleMesh> mesh;
  double fieldResolution = 2;   // mesh: its distance field's samples per grid cell and axis
  glm::dvec3 velocityMPerS{0.0};
  glm::dvec3 angularVelocityRadPerS{0.0};
  double friction = 0.3;        // Coulomb μ against the snow, the colliders and the walls
  Boundary boundary = Boundary::Separate;
  // From the shape and "mass" or "density" (the loader fills them): the mass, the volume, where the centre of mass
  // is at t = 0, and the inertia tensor about it along the body's own axes.
  double massKg = 0;
  double volumeM3 = 0;
  glm::dvec3 centerOfMassM{0.0};
  glm::dmat3 inertiaKgM2{0.0};
  // A spare body that waits outside the simulation (no gravity, no contacts, no snow) until
  // Simulation::launchRigidBody sets it going: the viewer's balls to throw (key O). Never read from a scene file.
  bool parked = false;
};

// How the snow's surface is reconstructed from the particles (docs/surfaces.md): for `--render surface`, `--mesh`
// and `--vdb`. The field is the particles' volume fraction smoothed by a kernel of `smoothing` particle spacings
// (each particle's V^(1/3)), sampled on nodes `resolution` times finer than the simulation's cells, and the
// surface is where it crosses `iso`.
struct SurfaceSpec {
  double resolution = 2;  // reconstruction cells per simulation cell, per axis
  double smoothing = 3;   // the kernel's support radius over the particle's spacing V^(1/3)
  double iso = 0.5;       // the volume fraction on the surface: ½ puts a flat edge where the particles' cells end
};

// Where pictures are taken from (`firn run --png`, the viewer's starting view).
struct CameraSpec {
  glm::dvec3 positionM{0.0};
  glm::dvec3 targetM{0.0};
  double fovDeg = 40;  // vertical field of view
};

struct Scene {
  std::string name;
  std::string description;
  std::filesystem::path sourcePath;  // empty for the built-in scene
  GridSpec grid;
  TimeSpec time;
  glm::dvec3 gravityMPerS2{0, -9.81, 0};
  SolverSpec solver;
  std::vector<Material> materials;
  std::vector<Body> bodies;
  std::vector<Collider> colliders;
  std::vector<RigidBody> rigidBodies;
  std::optional<CameraSpec> camera;  // absent: the renderer frames the scene itself
  SurfaceSpec surface;

  glm::dvec3 domainMinM() const { return grid.originM; }
  glm::dvec3 domainMaxM() const { return grid.originM + glm::dvec3(grid.cells) * grid.cellSizeM; }
};

// One particle as sampled from a body, before the GPU takes it over.
struct ParticleSeed {
  glm::vec3 positionM;
  glm::vec3 velocityMPerS;
  float massKg;
  int materialIndex;
  int bodyIndex;
  double releaseTimeS = 0;  // emitters: when the particle joins the simulation; 0 for everything else
};

// How messages name the built-in scene, which has no file.
constexpr const char* kBuiltInSceneName = "<built-in default scene>";
// The scene's file as messages name it (kBuiltInSceneName for the built-in scene).
std::string sceneFileName(const Scene& scene);

// The largest scene file read (docs/scene-format.md, Sizes and limits): the shipped scenes are a few kilobytes,
// and particles too many to list in a scene come from point files.
constexpr std::uintmax_t kMaxSceneFileBytes = 16u << 20;

// Reads and validates a scene file; throws InputError naming the file, the key and the problem. Only a regular
// file of at most kMaxSceneFileBytes is read (io/InputFile.h): a pipe or device is refused without blocking.
Scene loadScene(const std::filesystem::path& path);
// Same, from text; `source` names the file in messages.
Scene parseScene(const std::string& jsonText, const std::filesystem::path& source);
// The built-in scene `firn run` uses with no SCENE: assets/scenes/snowball_wall.json, a snowball thrown at a
// wall, compiled into the binary.
Scene defaultScene();
// Every assets/scenes/*.json, by file name (generated by cmake/EmbedFiles.cmake).
const std::map<std::string, std::string>& embeddedSceneFiles();
// The material presets a scene may name: dry, wet, icy, slushy, stomakhin.
const std::vector<Material>& snowPresets();

// Jittered lattice sampling of every body (fixed seed, so a scene always gives the same particles).
std::vector<ParticleSeed> sampleBodies(const Scene& scene);

}  // namespace firn
