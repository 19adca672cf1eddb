#pragma once
// OpenVDB caches of the snow (frame_NNNN.vdb): a float `density` grid and a narrow-band level set `surface`
// (docs/command-line.md, VDB caches), which Houdini and Blender open as they are.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "io/SurfaceMesh.h"

namespace firn {

// Samples of a field on a box of a lattice: node (i, j, k) of the lattice sits at originM + spacingM (i, j, k);
// the box holds nodes firstNode … firstNode + nodeCounts − 1, values x fastest, then y, then z.
struct LatticeSamples {
  glm::dvec3 originM{0.0};
  double spacingM = 1;
  glm::ivec3 firstNode{0};
  glm::ivec3 nodeCounts{0};
  std::vector<float> values;
};

struct VdbFrame {
  LatticeSamples density;  // the smoothed volume fraction (1: material at its rest density)
  // The snow's velocity (m/s) at the nodes of density's box, in its order; none: no `v` grid.
  std::vector<glm::vec3> velocityMPerS;
  float isoLevel = 0.5f;   // where the surface is; `density` is kept only inside it
  SurfaceMesh surface;     // closed, in metres: the level set is made from it
  int frame = 0;
  double timeS = 0;
};

// Writes `density` (class fog volume: the field at and inside the surface, 0 outside) and `surface` (class level
// set: the signed distance to the mesh in metres, negative inside, in a band of ±3 voxels; background 3 voxels)
// on one transform, voxel (i, j, k) at the lattice's node (i, j, k); with velocities, also `v` (a vector grid,
// the name Blender and Houdini read for motion blur: m/s, at the voxels where density is at least
// kVdbVelocityMinimumDensity, 0 elsewhere). Each grid's metadata names the units
// ("meters"), the voxel size in metres ("voxel_size_m"), the frame, its time and Firn; `density` also its iso
// level. The file is made in memory and written through a temporary file and a rename (io/AtomicFile.h): a disk
// that fills is an InputError naming the file and leaves no partial file. Its archive id (a UUID, random in
// OpenVDB) is derived from the content, so the same frame gives the same bytes.
void writeVdb(const std::filesystem::path& path, const VdbFrame& frame);

// Where the `v` grid holds the velocity: wherever the volume fraction reaches 1% of the rest density, which is
// past the surface (f = iso) by most of a kernel radius, so that a renderer moving the density along v finds
// the snow's velocity ahead of it as well as inside it.
constexpr float kVdbVelocityMinimumDensity = 0.01f;

// The narrow band's half width of the `surface` level set, in voxels (OpenVDB's LEVEL_SET_HALF_WIDTH).
constexpr double kVdbLevelSetHalfWidthVoxels = 3;

}  // namespace firn
