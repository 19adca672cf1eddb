#pragma once
// PLY point caches: binary little-endian, one vertex per particle with float properties
// x y z vx vy vz mass plastic_j (Blender, Houdini and assimp read them).
#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

namespace firn {

struct PointCache {
  std::vector<glm::vec3> positionsM;
  std::vector<glm::vec3> velocitiesMPerS;
  std::vector<float> massesKg;
  std::vector<float> plasticJ;
  bool hasMass = false;  // read: the file has a "mass" property (otherwise massesKg holds zeros)
  std::size_t size() const { return positionsM.size(); }
};

// Writes through a temporary file and a rename, so a reader never sees a half-written cache.
// Throws InputError naming the file if it cannot be written, and std::invalid_argument if a value is not
// finite (a non-finite value must never reach an output).
void writePly(const std::filesystem::path& path, const PointCache& points);

// Reads the vertices of a PLY file with at least x y z; vx vy vz, mass and plastic_j are read when present,
// other properties are skipped. Binary little-endian and ASCII, any PLY scalar type (a cloud made elsewhere
// often has double coordinates and uchar colours). Throws InputError naming the file and the problem.
PointCache readPly(const std::filesystem::path& path);

}  // namespace firn
