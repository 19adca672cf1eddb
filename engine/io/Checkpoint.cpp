#include "io/Checkpoint.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "Error.h"
#include "io/AtomicFile.h"

namespace firn {
namespace {

constexpr char kMagic[8] = {'F', 'I', 'R', 'N', 'C', 'K', 'P', 'T'};

template <class T>
void append(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);  // little-endian hosts only (x86-64, ARM64)
}

class Reader {
 public:
  Reader(const std::string& bytes, const std::filesystem::path& path) : bytes_(bytes), path_(path) {}
  template <class T>
  T next() {
    T value;
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  std::string nextBytes(std::size_t size) { return std::string(take(size), size); }

 private:
  const char* take(std::size_t size) {
    if (size > bytes_.size() - offset_) {
      throw InputError(path_.string() + ": truncated checkpoint (" + std::to_string(bytes_.size()) + " bytes)");
    }
    const char* start = bytes_.data() + offset_;
    offset_ += size;
    return start;
  }
  const std::string& bytes_;
  const std::filesystem::path& path_;
  std::size_t offset_ = 0;
};

}  // namespace

std::uint64_t fingerprint(const void* bytes, std::size_t size, std::uint64_t seed) {
  std::uint64_t hash = seed;
  const auto* data = static_cast<const unsigned char*>(bytes);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= data[i];
    hash *= 1099511628211ull;
  }
  return hash;
}

void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
  std::string out(kMagic, sizeof kMagic);
  append(out, Checkpoint::kVersion);
  append(out, checkpoint.sceneFingerprint);
  append(out, checkpoint.frame);
  append(out, checkpoint.timeS);
  append(out, checkpoint.steps);
  append(out, checkpoint.particleCount);
  append(out, checkpoint.releasedEmitterParticles);
  append(out, checkpoint.fastestSpeedMPerS);
  append(out, static_cast<std::uint64_t>(checkpoint.buffers.size()));
  for (const std::string& buffer : checkpoint.buffers) {
    append(out, static_cast<std::uint64_t>(buffer.size()));
    out += buffer;
  }
  writeFileAtomically(path, out, "checkpoint");
}

Checkpoint readCheckpoint(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open checkpoint (" + std::strerror(errno) + ")");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Reader reader(bytes, path);
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    throw InputError(path.string() + ": not a Firn checkpoint");
  }
  reader.nextBytes(sizeof kMagic);
  const auto version = reader.next<std::uint32_t>();
  if (version != Checkpoint::kVersion) {
    throw InputError(path.string() + ": checkpoint format version " + std::to_string(version) + ", this build reads " +
                     std::to_string(Checkpoint::kVersion));
  }
  Checkpoint checkpoint;
  checkpoint.sceneFingerprint = reader.next<std::uint64_t>();
  checkpoint.frame = reader.next<std::int32_t>();
  checkpoint.timeS = reader.next<double>();
  checkpoint.steps = reader.next<std::uint64_t>();
  checkpoint.particleCount = reader.next<std::uint64_t>();
  checkpoint.releasedEmitterParticles = reader.next<std::uint64_t>();
  checkpoint.fastestSpeedMPerS = reader.next<double>();
  const auto bufferCount = reader.next<std::uint64_t>();
  for (std::uint64_t i = 0; i < bufferCount; ++i) {
    const auto size = reader.next<std::uint64_t>();
    checkpoint.buffers.push_back(reader.nextBytes(size));
  }
  return checkpoint;
}

}  // namespace firn
