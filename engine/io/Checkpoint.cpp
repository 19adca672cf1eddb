#include "io/Checkpoint.h"

#include <zlib.h>

#include <cstring>
#include <limits>

#include "Error.h"
#include "io/AtomicFile.h"
#include "io/InputFile.h"

namespace firn {
namespace {

constexpr char kMagic[8] = {'F', 'I', 'R', 'N', 'C', 'K', 'P', 'T'};
// A simulation's state is a handful of buffers (sim/GpuState.cpp); a count beyond this is a damaged header.
constexpr std::uint64_t kMostBuffers = 64;

template <class T>
void append(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);  // little-endian hosts only (x86-64, ARM64)
}

// zlib's CRC-32 (ISO 3309, the checksum of gzip and PNG).
std::uint32_t crc32Of(const char* bytes, std::size_t size) {
  return static_cast<std::uint32_t>(crc32_z(crc32_z(0, nullptr, 0), reinterpret_cast<const Bytef*>(bytes), size));
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
  const char* take(std::size_t size) {
    if (size > remaining()) {
      throw InputError(path_.string() + ": truncated checkpoint (" + std::to_string(bytes_.size()) + " bytes)");
    }
    const char* start = bytes_.data() + offset_;
    offset_ += size;
    return start;
  }
  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return bytes_.size() - offset_; }

 private:
  const std::string& bytes_;
  const std::filesystem::path& path_;
  std::size_t offset_ = 0;
};

[[noreturn]] void failCorrupt(const std::filesystem::path& path, const std::string& problem) {
  throw InputError(path.string() + ": corrupt checkpoint: " + problem +
                   " (the file was damaged or changed after it was written)");
}

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
  for (const std::int64_t value : checkpoint.energyIntegers) append(out, value);
  for (const double value : checkpoint.energyReals) append(out, value);
  append(out, static_cast<std::uint64_t>(checkpoint.objectLoads.size()));
  for (const std::int64_t value : checkpoint.objectLoads) append(out, value);
  append(out, checkpoint.objectLoadDurationS);
  append(out, static_cast<std::uint64_t>(checkpoint.buffers.size()));
  for (const std::string& buffer : checkpoint.buffers) append(out, static_cast<std::uint64_t>(buffer.size()));
  append(out, crc32Of(out.data(), out.size()));
  for (const std::string& buffer : checkpoint.buffers) {
    out += buffer;
    append(out, crc32Of(buffer.data(), buffer.size()));
  }
  writeFileAtomically(path, out, "checkpoint");
}

Checkpoint readCheckpoint(const std::filesystem::path& path) {
  const std::string bytes = readRegularFile(path, "checkpoint", std::numeric_limits<std::uintmax_t>::max());
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    throw InputError(path.string() + ": not a Firn checkpoint");
  }
  Reader reader(bytes, path);
  reader.take(sizeof kMagic);
  const auto version = reader.next<std::uint32_t>();
  if (version != Checkpoint::kVersion) {
    const std::string which = version < Checkpoint::kVersion ? "an earlier" : "a later";
    throw InputError(path.string() + ": checkpoint format version " + std::to_string(version) + ", written by " +
                     which + " Firn; this build reads version " + std::to_string(Checkpoint::kVersion) +
                     " only, so run the scene again from frame 0 to make new checkpoints");
  }
  Checkpoint checkpoint;
  checkpoint.sceneFingerprint = reader.next<std::uint64_t>();
  checkpoint.frame = reader.next<std::int32_t>();
  checkpoint.timeS = reader.next<double>();
  checkpoint.steps = reader.next<std::uint64_t>();
  checkpoint.particleCount = reader.next<std::uint64_t>();
  checkpoint.releasedEmitterParticles = reader.next<std::uint64_t>();
  checkpoint.fastestSpeedMPerS = reader.next<double>();
  for (std::int64_t& value : checkpoint.energyIntegers) value = reader.next<std::int64_t>();
  for (double& value : checkpoint.energyReals) value = reader.next<double>();
  const auto loads = reader.next<std::uint64_t>();
  // Each load precedes the header's checksum, which covers it: a count that could not be right is a damaged header.
  if (loads > reader.remaining() / sizeof(std::int64_t)) {
    failCorrupt(path, "the header lists " + std::to_string(loads) + " object loads, more than a checkpoint of " +
                          std::to_string(bytes.size()) + " bytes can hold");
  }
  for (std::uint64_t i = 0; i < loads; ++i) checkpoint.objectLoads.push_back(reader.next<std::int64_t>());
  checkpoint.objectLoadDurationS = reader.next<double>();
  const auto bufferCount = reader.next<std::uint64_t>();
  // The count precedes the header's checksum, which covers it: a count that could not be right is a damaged header.
  if (bufferCount > kMostBuffers || bufferCount * sizeof(std::uint64_t) + sizeof(std::uint32_t) > reader.remaining()) {
    failCorrupt(path, "the header lists " + std::to_string(bufferCount) + " buffers, more than a checkpoint of " +
                          std::to_string(bytes.size()) + " bytes can hold");
  }
  std::vector<std::uint64_t> sizes;
  for (std::uint64_t i = 0; i < bufferCount; ++i) sizes.push_back(reader.next<std::uint64_t>());
  const std::size_t headerBytes = reader.offset();
  if (reader.next<std::uint32_t>() != crc32Of(bytes.data(), headerBytes)) {
    failCorrupt(path, "the header's CRC-32 does not match its bytes");
  }
  // The header is sound: a file shorter or longer than it says was cut short or has bytes appended.
  std::uint64_t expectedBytes = 0;
  for (std::uint64_t size : sizes) {
    const std::uint64_t left = reader.remaining() - expectedBytes;
    if (left < sizeof(std::uint32_t) || size > left - sizeof(std::uint32_t)) {
      throw InputError(path.string() + ": truncated checkpoint (" + std::to_string(bytes.size()) +
                       " bytes, fewer than its header lists)");
    }
    expectedBytes += size + sizeof(std::uint32_t);
  }
  if (expectedBytes < reader.remaining()) {
    failCorrupt(path, std::to_string(reader.remaining() - expectedBytes) + " bytes follow the last buffer");
  }
  for (std::uint64_t i = 0; i < bufferCount; ++i) {
    const char* buffer = reader.take(sizes[i]);
    if (reader.next<std::uint32_t>() != crc32Of(buffer, sizes[i])) {
      failCorrupt(path, "the CRC-32 of buffer " + std::to_string(i + 1) + " of " + std::to_string(bufferCount) +
                            " does not match its bytes");
    }
    checkpoint.buffers.emplace_back(buffer, sizes[i]);
  }
  return checkpoint;
}

}  // namespace firn
