// The scene file's "bodies": sphere and box bodies, and mesh and points bodies with their files loaded and
// placed, each checked to lie inside the simulation interior (docs/scene-format.md).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include "Error.h"
#include "io/PointCloud.h"
#include "io/Text.h"
#include "scene/Sampling.h"
#include "scene/SceneSections.h"
#include "voxelizer/Mesh.h"

namespace firn::scenefile {

using json::Interval;
using json::Object;
using json::Value;
using json::describeValue;
using json::joinNames;

namespace {

int readMaterialReference(const Object& body, const std::vector<Material>& materials) {
  const Value reference = body.required("material");
  const std::string name = reference.string();
  std::vector<std::string> names;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].name == name) return static_cast<int>(i);
    names.push_back(materials[i].name);
  }
  reference.fail("no material named " + describeValue(reference.json()) + " (materials: " + joinNames(names) + ")");
}

voxelizer::Transform readPlacement(const Object& body) {
  voxelizer::Transform placement;
  placement.scale = body.number("scale", placement.scale, Interval::greaterThan(0));
  placement.rotateDeg = body.vec3("rotate_deg", placement.rotateDeg);
  placement.translateM = body.vec3("translate", placement.translateM);
  return placement;
}

std::filesystem::path readFilePath(const Object& object, const std::filesystem::path& sceneFolder, std::string& path) {
  path = object.required("path").string();
  if (path.empty()) object.fail("path", "must not be empty");
  return sceneFolder / path;
}

void loadPointsBody(const Object& body, Body& result, const voxelizer::Transform& placement, const GridSpec& grid,
                    double densityKgPerM3) {
  PointCloud cloud;
  try {
    cloud = readPointCloud(result.resolvedPath);
  } catch (const InputError& error) {
    body.fail("path", error.what());
  }
  const glm::dmat3 rotation = voxelizer::rotationMatrix(placement.rotateDeg);
  std::vector<glm::dvec3> points;
  points.reserve(cloud.positionsM.size());
  result.loadedMinM = glm::dvec3(std::numeric_limits<double>::infinity());
  result.loadedMaxM = -result.loadedMinM;
  for (const glm::dvec3& p : cloud.positionsM) {
    const glm::dvec3& placed = points.emplace_back(placement.translateM + rotation * (placement.scale * p));
    // A scale or translation near the limits of a double can carry a point to infinity (or NaN, ∞ − ∞).
    if (!std::isfinite(placed.x) || !std::isfinite(placed.y) || !std::isfinite(placed.z)) {
      body.value().fail("placing the cloud (scale, rotate_deg, translate) takes a point beyond the range of a double");
    }
    result.loadedMinM = glm::min(result.loadedMinM, placed);
    result.loadedMaxM = glm::max(result.loadedMaxM, placed);
  }
  result.pointSpacingM = medianNeighbourSpacingM(points);
  if (!std::isfinite(result.pointSpacingM)) {
    body.value().fail("the placed cloud's points are further apart than a double can measure");
  }
  if (result.pointSpacingM > 0) result.particlesPerCell = std::pow(grid.cellSizeM / result.pointSpacingM, 3.0);

  if (body.has("particle_mass")) {
    result.pointMassesKg = {body.number("particle_mass", Interval::greaterThan(0))};
  } else if (!cloud.massesKg.empty()) {
    // The file's masses belong to the cloud at its own size; scaled by s, it covers s³ the volume.
    const double volumeRatio = placement.scale * placement.scale * placement.scale;
    for (double massKg : cloud.massesKg) result.pointMassesKg.push_back(massKg * volumeRatio);
  } else if (result.pointSpacingM > 0) {
    result.pointMassesKg = {densityKgPerM3 * result.pointSpacingM * result.pointSpacingM * result.pointSpacingM};
  } else {
    body.fail("particle_mass", "required key is missing: the cloud's points coincide, so no spacing (and no mass "
                               "from the density) can be derived from it");
  }
  result.pointsM = std::make_shared<const std::vector<glm::dvec3>>(std::move(points));
}

// Masses live in 32-bit floats on the GPU: each must be a normal float, neither 0 nor infinite after rounding
// (extreme densities, spacings, scales or mass_scale can produce either).
void checkParticleMasses(const Object& body, const Body& result, const GridSpec& grid, const Material& material) {
  const auto check = [&](double massKg, const std::string& origin) {
    const double scaledKg = massKg * result.massScale;
    if (!(scaledKg >= double(std::numeric_limits<float>::min()) && scaledKg <= double(std::numeric_limits<float>::max()))) {
      body.value().fail("a particle's mass, " + formatApproximately(scaledKg) + " kg (" + origin +
                        "), is outside what the GPU's 32-bit floats hold; change the density, scale or mass_scale");
    }
  };
  if (result.shape == BodyShape::Points) {
    const auto [lightest, heaviest] = std::minmax_element(result.pointMassesKg.begin(), result.pointMassesKg.end());
    check(*lightest, "the lightest of the cloud's");
    check(*heaviest, "the heaviest of the cloud's");
    return;
  }
  const double spacingM = grid.cellSizeM / std::cbrt(result.particlesPerCell);
  check(material.densityKgPerM3 * spacingM * spacingM * spacingM, "density × spacing³ × mass_scale");
}

}  // namespace

PlacedMesh readPlacedMesh(const Object& object, const std::filesystem::path& sceneFolder, double spacingM) {
  PlacedMesh result;
  result.resolvedPath = readFilePath(object, sceneFolder, result.path);
  result.placement = readPlacement(object);
  voxelizer::TriangleMesh mesh;
  try {
    mesh = voxelizer::transformed(voxelizer::loadMesh(result.resolvedPath), result.placement);
  } catch (const voxelizer::MeshError& error) {
    object.fail("path", error.what());
  }
  const std::string problem = voxelizer::whyNotFillable(mesh, voxelizer::measureSurface(mesh), spacingM);
  if (!problem.empty()) object.fail("path", result.resolvedPath.string() + ": " + problem);
  result.mesh = std::make_shared<const voxelizer::TriangleMesh>(std::move(mesh));
  return result;
}

Body readBody(const Object& body, const GridSpec& grid, const std::vector<Material>& materials,
              const std::filesystem::path& sceneFolder) {
  Body result;
  result.shape = body.required("shape").choice<BodyShape>(
      {{"sphere", BodyShape::Sphere}, {"box", BodyShape::Box}, {"mesh", BodyShape::Mesh}, {"points", BodyShape::Points}});
  const auto keysWith = [](const std::vector<std::string>& shapeKeys) {
    std::vector<std::string> keys = {"shape"};
    keys.insert(keys.end(), shapeKeys.begin(), shapeKeys.end());
    for (const char* common : {"material", "velocity", "angular_velocity", "lambda_scale", "mu_scale", "mass_scale",
                               "start_frame", "duration_frames"}) {
      keys.push_back(common);
    }
    return keys;
  };
  const auto readFile = [&] { result.resolvedPath = readFilePath(body, sceneFolder, result.path); };
  switch (result.shape) {
    case BodyShape::Sphere:
      body.checkKeys(keysWith({"center", "radius", "particles_per_cell", "sampler"}), "a sphere body");
      result.centerM = body.vec3("center");
      result.radiusM = body.number("radius", Interval::greaterThan(0));
      break;
    case BodyShape::Box:
      body.checkKeys(keysWith({"min", "max", "particles_per_cell", "sampler"}), "a box body");
      result.minM = body.vec3("min");
      result.maxM = body.vec3("max");
      checkBoxCorners(body, result.minM, result.maxM);
      break;
    case BodyShape::Mesh:
      body.checkKeys(keysWith({"path", "scale", "rotate_deg", "translate", "particles_per_cell", "sampler"}), "a mesh body");
      readFile();
      break;
    case BodyShape::Points:
      body.checkKeys(keysWith({"path", "scale", "rotate_deg", "translate", "particle_mass"}), "a points body");
      readFile();
      break;
  }
  result.materialIndex = readMaterialReference(body, materials);
  result.velocityMPerS = body.vec3("velocity", result.velocityMPerS);
  result.angularVelocityRadPerS = body.vec3("angular_velocity", result.angularVelocityRadPerS);
  result.lambdaScale = body.number("lambda_scale", result.lambdaScale, Interval::atLeast(0));
  result.muScale = body.number("mu_scale", result.muScale, Interval::atLeast(0));
  // Either scale alone may be 0 (λ = 0: no resistance to volume change beyond μ's; μ = 0: a compressible fluid).
  // Both at 0 leave the body no elastic stress: nothing resists its compression, and it has no wave speed to bound
  // the step. Water's stress comes from its bulk modulus, which the scales do not touch.
  if (result.lambdaScale == 0 && result.muScale == 0 &&
      materials[std::size_t(result.materialIndex)].model != MaterialModel::Water) {
    body.fail("mu_scale", "must not be 0 together with lambda_scale: with both 0 the body has no elastic stress, so "
                          "nothing resists its compression (its particles pile into ever fewer cells) and no elastic "
                          "wave bounds its time step; give one of them a value above 0");
  }
  result.massScale = body.number("mass_scale", result.massScale, Interval::greaterThan(0));
  constexpr int maxFrames = 1000000;  // as time.frames
  result.startFrame = body.integer("start_frame", result.startFrame, 0, maxFrames);
  result.durationFrames = body.integer("duration_frames", result.durationFrames, 0, maxFrames);
  result.particlesPerCell = body.number("particles_per_cell", result.particlesPerCell, Interval::openClosed(0, 1000));
  result.sampler = body.choice<BodySampler>("sampler", result.sampler,
                                            {{"lattice", BodySampler::Lattice}, {"poisson_disk", BodySampler::PoissonDisk}});
  if (result.shape == BodyShape::Mesh) {
    PlacedMesh placed = readPlacedMesh(body, sceneFolder, particleSpacingM(result, grid));
    const voxelizer::Bounds box = voxelizer::bounds(*placed.mesh);
    result.loadedMinM = box.minM;
    result.loadedMaxM = box.maxM;
    result.mesh = std::move(placed.mesh);
  }
  if (result.shape == BodyShape::Points) {
    loadPointsBody(body, result, readPlacement(body), grid,
                   materials[std::size_t(result.materialIndex)].densityKgPerM3);
  }

  checkParticleMasses(body, result, grid, materials[std::size_t(result.materialIndex)]);

  checkInsideInterior(body, "body", result.boundsMinM(), result.boundsMaxM(), grid);
  return result;
}

void checkInsideInterior(const Object& object, const std::string& what, const glm::dvec3& minM,
                         const glm::dvec3& maxM, const GridSpec& grid) {
  const glm::dvec3 interiorMinM = grid.interiorMinM();
  const glm::dvec3 interiorMaxM = grid.interiorMaxM();
  if (!glm::all(glm::greaterThanEqual(minM, interiorMinM)) || !glm::all(glm::lessThanEqual(maxM, interiorMaxM))) {
    object.value().fail("the " + what + " reaches outside the simulation interior: its bounding box is " +
                        describeBox(minM, maxM) + ", the interior (the grid less " +
                        std::to_string(GridSpec::wallCells) + " wall cells on each side) is " +
                        describeBox(interiorMinM, interiorMaxM));
  }
}

}  // namespace firn::scenefile
