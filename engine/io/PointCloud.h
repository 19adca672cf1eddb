#pragma once
// Point clouds made elsewhere, for `"shape": "points"` bodies: PLY, or text with one point per line.
#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

namespace firn {

struct PointCloud {
  std::vector<glm::dvec3> positionsM;
  std::vector<double> massesKg;  // from a PLY "mass" property; empty when the file has none
};

// A file ending in .ply (any case) is read as PLY (io/Ply.h); anything else as text, one point per line as
// "x,y,z" or "x y z" ('#' starts a comment, blank lines are skipped). Throws InputError naming the file (and
// the line, for text) and the problem: unreadable, malformed, a non-finite coordinate, or no points at all.
PointCloud readPointCloud(const std::filesystem::path& path);

// The median over the points of the distance to the nearest other point: the spacing of a lattice-like
// cloud (exactly the lattice spacing when it is unjittered). 0 for fewer than two points.
double medianNeighbourSpacingM(const std::vector<glm::dvec3>& positionsM);

}  // namespace firn
