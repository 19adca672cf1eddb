#include "io/PointCloud.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <unordered_map>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "Error.h"
#include "io/InputFile.h"
#include "io/Ply.h"

namespace firn {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) {
  throw InputError(path.string() + ": " + problem);
}

bool isFinite(const glm::dvec3& point) {
  return std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z);
}

bool hasPlyExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension == ".ply";
}

// One "x,y,z" or "x y z" line; false if it does not hold exactly three numbers.
bool parsePoint(const std::string& line, glm::dvec3& point) {
  const char* cursor = line.data();
  const char* const end = line.data() + line.size();
  int count = 0;
  while (true) {
    while (cursor < end && (std::isspace(static_cast<unsigned char>(*cursor)) || *cursor == ',')) ++cursor;
    if (cursor == end) break;
    if (count == 3) return false;
    double value = 0;
    const auto [next, error] = std::from_chars(cursor, end, value);
    if (error != std::errc() || next == cursor) return false;
    point[count++] = value;
    cursor = next;
  }
  return count == 3;
}

PointCloud readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) fail(path, std::string("cannot open point cloud (") + std::strerror(errno) + ")");
  PointCloud cloud;
  std::string line;
  std::size_t lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::size_t comment = line.find('#');
    if (comment != std::string::npos) line.erase(comment);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    glm::dvec3 point;
    if (!parsePoint(line, point)) {
      fail(path, "line " + std::to_string(lineNumber) + ": expected three numbers \"x,y,z\" (got \"" +
                     line.substr(0, 60) + "\")");
    }
    if (!isFinite(point)) fail(path, "line " + std::to_string(lineNumber) + ": a coordinate is not finite");
    cloud.positionsM.push_back(point);
  }
  if (in.bad()) fail(path, "reading the point cloud failed");
  return cloud;
}

PointCloud readPlyCloud(const std::filesystem::path& path) {
  const PointCache cache = readPly(path);
  PointCloud cloud;
  cloud.positionsM.reserve(cache.size());
  for (std::size_t i = 0; i < cache.size(); ++i) {
    const glm::dvec3 point(cache.positionsM[i]);
    if (!isFinite(point)) fail(path, "vertex " + std::to_string(i) + ": a coordinate is not finite");
    cloud.positionsM.push_back(point);
  }
  if (cache.hasMass) {
    for (std::size_t i = 0; i < cache.size(); ++i) {
      const double massKg = cache.massesKg[i];
      if (!(massKg > 0) || !std::isfinite(massKg)) {
        fail(path, "vertex " + std::to_string(i) + ": mass must be positive and finite (got " + std::to_string(massKg) + ")");
      }
      cloud.massesKg.push_back(massKg);
    }
  }
  return cloud;
}

}  // namespace

PointCloud readPointCloud(const std::filesystem::path& path) {
  // Only regular files are read: a folder fails on the first read, and a device or pipe can be endless
  // (/dev/zero holds no line break, so reading its first line would never finish).
  requireRegularFile(path, "point cloud");
  PointCloud cloud = hasPlyExtension(path) ? readPlyCloud(path) : readText(path);
  if (cloud.positionsM.empty()) fail(path, "the point cloud holds no points");
  return cloud;
}

double medianNeighbourSpacingM(const std::vector<glm::dvec3>& positionsM) {
  if (positionsM.size() < 2) return 0;
  glm::dvec3 low(std::numeric_limits<double>::infinity()), high(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : positionsM) {
    low = glm::min(low, p);
    high = glm::max(high, p);
  }
  const glm::dvec3 extent = high - low;
  // The points must be finite (a NaN has no cell). A cloud wider than a double can measure has no spacing a
  // double can hold, and its cells could not be indexed.
  if (!std::isfinite(extent.x) || !std::isfinite(extent.y) || !std::isfinite(extent.z)) {
    return std::numeric_limits<double>::infinity();
  }
  const double largestExtent = std::max({extent.x, extent.y, extent.z});
  const double count = double(positionsM.size());
  // A hash grid whose cells hold about one point, whether the cloud fills a volume, a sheet or a line. For a
  // flat cloud whose area overflows, the volume is ∞ · 0 = NaN, which fmax passes over.
  const double largestArea = std::max({extent.x * extent.y, extent.y * extent.z, extent.z * extent.x});
  double cellM = std::fmax(std::fmax(std::cbrt(extent.x * extent.y * extent.z / count), std::sqrt(largestArea / count)),
                           largestExtent / count);
  if (!(cellM > 0)) return 0;  // every point is the same point

  const auto cellOf = [&](const glm::dvec3& p) { return glm::i64vec3(glm::floor((p - low) / cellM)); };
  const auto key = [](const glm::i64vec3& c) {
    return std::uint64_t(c.x) * 73856093u ^ std::uint64_t(c.y) * 19349663u ^ std::uint64_t(c.z) * 83492791u;
  };
  // Each point's nearest neighbour is searched for within a few cells only: the median needs exact distances
  // for the nearer half of the points, not for isolated outliers. If more than half are isolated, the cells
  // were too small for this cloud, and the search is repeated with larger ones.
  constexpr std::int64_t searchRings = 3;
  std::vector<double> nearest(positionsM.size());
  while (true) {
    std::unordered_multimap<std::uint64_t, std::size_t> cells;
    cells.reserve(positionsM.size());
    for (std::size_t i = 0; i < positionsM.size(); ++i) cells.emplace(key(cellOf(positionsM[i])), i);
    for (std::size_t i = 0; i < positionsM.size(); ++i) {
      const glm::i64vec3 center = cellOf(positionsM[i]);
      double bestSquared = std::numeric_limits<double>::infinity();
      for (std::int64_t ring = 1; ring <= searchRings; ++ring) {
        for (std::int64_t z = -ring; z <= ring; ++z)
          for (std::int64_t y = -ring; y <= ring; ++y)
            for (std::int64_t x = -ring; x <= ring; ++x) {
              // Only the shell of this ring: the inside was searched by the rings before.
              if (ring > 1 && std::max({std::abs(x), std::abs(y), std::abs(z)}) != ring) continue;
              const glm::i64vec3 cell = center + glm::i64vec3(x, y, z);
              const auto [first, last] = cells.equal_range(key(cell));
              for (auto entry = first; entry != last; ++entry) {
                if (entry->second == i || cellOf(positionsM[entry->second]) != cell) continue;
                const glm::dvec3 offset = positionsM[entry->second] - positionsM[i];
                bestSquared = std::min(bestSquared, glm::dot(offset, offset));
              }
            }
        // Every point within `ring` cells of this one has been seen, so a neighbour that near is the nearest.
        if (bestSquared <= double(ring * ring) * cellM * cellM) break;
      }
      nearest[i] = bestSquared <= double(searchRings * searchRings) * cellM * cellM
                       ? std::sqrt(bestSquared)
                       : std::numeric_limits<double>::infinity();
    }
    const auto middle = nearest.begin() + std::ptrdiff_t(nearest.size() / 2);
    std::nth_element(nearest.begin(), middle, nearest.end());
    // Once one cell spans the whole cloud every pair has been compared, so the median is exact; it is infinite
    // only if the points are so far apart that their squared distances overflow.
    if (std::isfinite(*middle) || cellM >= largestExtent) return *middle;
    cellM *= 4;
  }
}

}  // namespace firn
