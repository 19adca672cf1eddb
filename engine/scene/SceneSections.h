#pragma once
// The readers of the scene file's larger sections (docs/scene-format.md), each in a file of its own:
// SceneMaterials.cpp, SceneBodies.cpp, SceneColliders.cpp, SceneRigidBodies.cpp and SceneSurface.cpp. SceneLoader.cpp reads the top
// level and the small sections (grid, time, solver, camera) and calls these. Internal to engine/scene.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/vector_relational.hpp>

#include "scene/JsonChecker.h"
#include "scene/Scene.h"
#include "voxelizer/Mesh.h"

namespace firn::scenefile {

// "materials": an object of named materials, in the file's order.
std::vector<Material> readMaterials(const json::Object& materials);

// One element of "bodies"; mesh and points files are read here, relative to `sceneFolder`.
Body readBody(const json::Object& body, const GridSpec& grid, const std::vector<Material>& materials,
              const std::filesystem::path& sceneFolder);

// One element of "colliders"; a mesh collider's file is read here, relative to `sceneFolder`.
Collider readCollider(const json::Object& collider, const GridSpec& grid, const std::filesystem::path& sceneFolder);

// "rigid_bodies": each body read, its mass properties derived, and checked to lie in the grid's interior and
// clear of the others (SceneRigidBodies.cpp).
std::vector<RigidBody> readRigidBodies(const json::Value& rigidBodies, const GridSpec& grid,
                                       const std::filesystem::path& sceneFolder);

// A mesh file as mesh bodies, mesh colliders and mesh rigid bodies name it: "path" (relative to the scene's
// folder) and the placement "scale", "rotate_deg" and "translate" (SceneBodies.cpp).
struct PlacedMesh {
  std::string path;
  std::filesystem::path resolvedPath;
  voxelizer::Transform placement;
  std::shared_ptr<const voxelizer::TriangleMesh> mesh;  // placed
};

// The file loaded through the guarded importer and placed; an unreadable file, or one whose placed mesh cannot
// be used (not finite, too far from the origin for float positions `spacingM` apart, flat), fails at "path"
// naming the file.
PlacedMesh readPlacedMesh(const json::Object& object, const std::filesystem::path& sceneFolder, double spacingM);

// "resolution" of a mesh collider's or rigid body's distance field, samples per grid cell and axis: below half a
// sample per cell the field rounds away features of the cell's size, which the snow resolves; beyond 8 the field
// (8³ = 512 samples per cell) outweighs the grid it serves.
inline json::Interval fieldResolutionAllowed() { return json::Interval::closed(0.5, 8); }

// "surface": the reconstruction of the snow's surface (SceneSurface.cpp).
SurfaceSpec readSurface(const json::Object& surface);

// "[x, y, z] to [x, y, z] m", for messages.
inline std::string describeBox(const glm::dvec3& minM, const glm::dvec3& maxM) {
  return json::describePoint(minM) + " to " + json::describePoint(maxM) + " m";
}

// Bodies of snow and rigid bodies alike start clear of the wall cells, where the grid update zeroes the velocity:
// fails at `object` ("the <what> reaches outside the simulation interior", with both boxes) if [minM, maxM] does not
// lie in the grid's interior (SceneBodies.cpp).
void checkInsideInterior(const json::Object& object, const std::string& what, const glm::dvec3& minM,
                         const glm::dvec3& maxM, const GridSpec& grid);

// Box bodies and box colliders alike.
inline void checkBoxCorners(const json::Object& box, const glm::dvec3& minM, const glm::dvec3& maxM) {
  if (!glm::all(glm::lessThan(minM, maxM))) {
    box.fail("max", "must exceed \"min\" on every axis (min " + json::describePoint(minM) + ", max " +
                        json::describePoint(maxM) + ")");
  }
}

}  // namespace firn::scenefile
