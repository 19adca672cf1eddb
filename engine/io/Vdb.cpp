#include "io/Vdb.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>

#include <openvdb/io/Archive.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include "io/AtomicFile.h"

namespace firn {

namespace {

// OpenVDB's file writer (io::File) writes straight to disk and does not check the stream after writing, so a
// disk that fills would leave a truncated file. An Archive writes the same bytes to any seekable stream (its
// write to a stream is protected, hence this subclass): here to memory, then through writeFileAtomically.
class InMemoryArchive : public openvdb::io::Archive {
 public:
  openvdb::io::Archive::Ptr copy() const override { return std::make_shared<InMemoryArchive>(*this); }
  std::string bytes(const openvdb::GridCPtrVec& grids) const {
    std::ostringstream out(std::ios::binary);
    write(out, grids, /*seekable=*/true, openvdb::MetaMap());
    if (!out) throw std::runtime_error("OpenVDB could not write the archive to memory");
    return out.str();
  }
};

// The header's archive id: 36 characters of a UUID after the magic number, the file and library versions and
// the grid-offsets flag (OpenVDB's io::Archive::writeHeader).
constexpr std::size_t kUuidOffset = 8 + 4 + 4 + 4 + 1;
constexpr std::size_t kUuidLength = 36;

std::uint64_t fnv1a(const std::string& bytes, std::size_t first, std::uint64_t hash) {
  for (std::size_t i = first; i < bytes.size(); ++i) {
    hash ^= static_cast<unsigned char>(bytes[i]);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

// OpenVDB gives each archive a random UUID. Here it is a hash of the rest of the file (two FNV-1a hashes with
// different starts, shaped as a name-based UUID), so that the same frame always gives the same bytes.
void replaceArchiveId(std::string& bytes) {
  const auto isUuid = [&] {
    if (bytes.size() < kUuidOffset + kUuidLength) return false;
    for (std::size_t i = 0; i < kUuidLength; ++i) {
      const char c = bytes[kUuidOffset + i];
      const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
      if (dash != (c == '-')) return false;
    }
    return true;
  };
  if (!isUuid()) throw std::logic_error("OpenVDB's file header is not laid out as io::Archive::writeHeader was");
  const std::uint64_t high = fnv1a(bytes, kUuidOffset + kUuidLength, 0xcbf29ce484222325ull);
  const std::uint64_t low = fnv1a(bytes, kUuidOffset + kUuidLength, 0x84222325cbf29ce4ull);
  char uuid[kUuidLength + 1];
  std::snprintf(uuid, sizeof uuid, "%08x-%04x-5%03x-%04x-%012llx", unsigned(high >> 32), unsigned((high >> 16) & 0xFFFF),
                unsigned(high & 0xFFF), unsigned(0x8000 | (low >> 48 & 0x3FFF)),
                static_cast<unsigned long long>(low & 0xFFFFFFFFFFFFull));
  bytes.replace(kUuidOffset, kUuidLength, uuid, kUuidLength);
}

openvdb::math::Transform::Ptr latticeTransform(const LatticeSamples& lattice) {
  openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(lattice.spacingM);
  transform->postTranslate(openvdb::Vec3d(lattice.originM.x, lattice.originM.y, lattice.originM.z));
  return transform;
}

void describe(openvdb::GridBase& grid, const LatticeSamples& lattice, const VdbFrame& frame) {
  grid.insertMeta("units", openvdb::StringMetadata("meters"));
  grid.insertMeta("voxel_size_m", openvdb::DoubleMetadata(lattice.spacingM));
  grid.insertMeta("frame", openvdb::Int32Metadata(frame.frame));
  grid.insertMeta("time_s", openvdb::DoubleMetadata(frame.timeS));
  grid.insertMeta("source", openvdb::StringMetadata("Firn (MPM snow): the snow's surface"));
}

}  // namespace

void writeVdb(const std::filesystem::path& path, const VdbFrame& frame) {
  static std::once_flag initialised;
  std::call_once(initialised, [] { openvdb::initialize(); });
  const LatticeSamples& lattice = frame.density;
  const glm::ivec3 counts = lattice.nodeCounts;
  if (lattice.values.size() != std::size_t(counts.x) * std::size_t(counts.y) * std::size_t(counts.z)) {
    throw std::invalid_argument("writeVdb: the density's values do not fill its box");
  }
  const openvdb::math::Transform::Ptr transform = latticeTransform(lattice);

  openvdb::FloatGrid::Ptr density = openvdb::FloatGrid::create(0.0f);
  density->setName("density");
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  density->setTransform(transform);
  {
    openvdb::FloatGrid::Accessor voxels = density->getAccessor();
    std::size_t i = 0;
    for (int z = 0; z < counts.z; ++z) {
      for (int y = 0; y < counts.y; ++y) {
        for (int x = 0; x < counts.x; ++x, ++i) {
          const float value = lattice.values[i];
          if (!std::isfinite(value)) throw std::invalid_argument("writeVdb: a density sample is not finite");
          if (value < frame.isoLevel) continue;  // outside the surface: the background, 0
          const glm::ivec3 node = lattice.firstNode + glm::ivec3(x, y, z);
          voxels.setValue(openvdb::Coord(node.x, node.y, node.z), value);
        }
      }
    }
  }
  describe(*density, lattice, frame);
  density->insertMeta("iso_level", openvdb::FloatMetadata(frame.isoLevel));
  density->insertMeta("quantity", openvdb::StringMetadata("volume fraction: 1 is snow at its rest density"));

  openvdb::Vec3SGrid::Ptr velocity;
  if (!frame.velocityMPerS.empty()) {
    if (frame.velocityMPerS.size() != lattice.values.size()) {
      throw std::invalid_argument("writeVdb: the velocities do not fill the density's box");
    }
    velocity = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    velocity->setName("v");
    velocity->setVectorType(openvdb::VEC_CONTRAVARIANT_RELATIVE);  // a velocity: transformed as a displacement
    velocity->setTransform(transform);
    openvdb::Vec3SGrid::Accessor voxels = velocity->getAccessor();
    std::size_t i = 0;
    for (int z = 0; z < counts.z; ++z) {
      for (int y = 0; y < counts.y; ++y) {
        for (int x = 0; x < counts.x; ++x, ++i) {
          if (lattice.values[i] < kVdbVelocityMinimumDensity) continue;
          const glm::vec3& v = frame.velocityMPerS[i];
          if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
            throw std::invalid_argument("writeVdb: a velocity sample is not finite");
          }
          const glm::ivec3 node = lattice.firstNode + glm::ivec3(x, y, z);
          voxels.setValue(openvdb::Coord(node.x, node.y, node.z), openvdb::Vec3s(v.x, v.y, v.z));
        }
      }
    }
    describe(*velocity, lattice, frame);
    velocity->insertMeta("quantity", openvdb::StringMetadata("the snow's velocity (m/s): the particles' velocities "
                                                             "weighted as density weighs them"));
  }

  std::vector<openvdb::Vec3s> points;
  points.reserve(frame.surface.positionsM.size());
  for (const glm::vec3& p : frame.surface.positionsM) points.emplace_back(p.x, p.y, p.z);
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(frame.surface.triangleCount());
  for (std::size_t t = 0; t < frame.surface.triangleCount(); ++t) {
    triangles.emplace_back(frame.surface.indices[3 * t], frame.surface.indices[3 * t + 1], frame.surface.indices[3 * t + 2]);
  }
  openvdb::FloatGrid::Ptr surface = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(
      *transform, points, triangles, float(kVdbLevelSetHalfWidthVoxels));
  surface->setName("surface");
  surface->setGridClass(openvdb::GRID_LEVEL_SET);
  describe(*surface, lattice, frame);
  openvdb::GridCPtrVec grids{density, surface};
  if (velocity) grids.push_back(velocity);

  std::string bytes = InMemoryArchive().bytes(grids);
  replaceArchiveId(bytes);
  writeFileAtomically(path, bytes, "VDB cache");
}

}  // namespace firn
