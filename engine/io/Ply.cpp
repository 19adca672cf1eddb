#include "io/Ply.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include "Error.h"

namespace firn {

namespace {

const char* const kPropertyNames[] = {"x", "y", "z", "vx", "vy", "vz", "mass", "plastic_j"};
constexpr std::size_t kPropertyCount = sizeof kPropertyNames / sizeof kPropertyNames[0];

void appendLittleEndian(std::string& out, float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (int byte = 0; byte < 4; ++byte) out.push_back(static_cast<char>((bits >> (8 * byte)) & 0xFFu));
}

float readLittleEndianFloat(const unsigned char* bytes) {
  const std::uint32_t bits = std::uint32_t(bytes[0]) | std::uint32_t(bytes[1]) << 8 | std::uint32_t(bytes[2]) << 16 |
                             std::uint32_t(bytes[3]) << 24;
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) {
  throw InputError(path.string() + ": " + problem);
}

}  // namespace

void writePly(const std::filesystem::path& path, const PointCache& points) {
  const std::size_t count = points.size();
  if (points.velocitiesMPerS.size() != count || points.massesKg.size() != count || points.plasticJ.size() != count) {
    throw std::invalid_argument("writePly: point cache fields have different lengths");
  }
  std::string data = "ply\nformat binary_little_endian 1.0\ncomment written by Firn\nelement vertex " +
                     std::to_string(count) + "\n";
  for (const char* name : kPropertyNames) data += std::string("property float ") + name + "\n";
  data += "end_header\n";
  data.reserve(data.size() + count * kPropertyCount * sizeof(float));
  for (std::size_t i = 0; i < count; ++i) {
    const float values[kPropertyCount] = {points.positionsM[i].x,      points.positionsM[i].y,
                                          points.positionsM[i].z,      points.velocitiesMPerS[i].x,
                                          points.velocitiesMPerS[i].y, points.velocitiesMPerS[i].z,
                                          points.massesKg[i],          points.plasticJ[i]};
    for (float value : values) {
      if (!std::isfinite(value)) {
        throw std::invalid_argument("writePly: particle " + std::to_string(i) + " has a non-finite value");
      }
      appendLittleEndian(data, value);
    }
  }
  std::filesystem::path temporary = path;
  temporary += ".part";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) fail(path, std::string("cannot write point cache (") + std::strerror(errno) + ")");
    out.write(data.data(), static_cast<std::streamsize>(data.size()));
    if (!out) fail(path, "writing the point cache failed (disk full?)");
  }
  std::filesystem::rename(temporary, path);
}

PointCache readPly(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, std::string("cannot open point cache (") + std::strerror(errno) + ")");
  std::string line;
  std::getline(in, line);
  if (line != "ply") fail(path, "not a PLY file (first line is not \"ply\")");

  bool binary = false;
  std::size_t vertexCount = 0;
  bool inVertexElement = false;
  std::vector<std::string> properties;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string format;
      words >> format;
      if (format == "binary_little_endian") binary = true;
      else if (format != "ascii") fail(path, "unsupported PLY format \"" + format + "\" (binary_little_endian or ascii)");
    } else if (keyword == "element") {
      std::string element;
      words >> element;
      inVertexElement = element == "vertex";
      if (inVertexElement) words >> vertexCount;
      else if (vertexCount == 0) fail(path, "elements before \"vertex\" are not supported");
    } else if (keyword == "property" && inVertexElement) {
      std::string type, name;
      words >> type >> name;
      if (type != "float" && type != "float32") fail(path, "vertex property \"" + name + "\" is " + type + "; only float is supported");
      properties.push_back(name);
    } else if (keyword == "end_header") {
      break;
    }
  }
  if (line != "end_header") fail(path, "PLY header has no end_header");
  std::map<std::string, std::size_t> column;
  for (std::size_t i = 0; i < properties.size(); ++i) column[properties[i]] = i;
  for (const char* required : {"x", "y", "z"}) {
    if (column.count(required) == 0) fail(path, std::string("vertex property \"") + required + "\" is missing");
  }

  std::vector<float> values(vertexCount * properties.size());
  if (binary) {
    std::vector<unsigned char> bytes(values.size() * sizeof(float));
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (static_cast<std::size_t>(in.gcount()) != bytes.size()) {
      fail(path, "truncated: the header declares " + std::to_string(vertexCount) + " vertices");
    }
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = readLittleEndianFloat(&bytes[i * sizeof(float)]);
  } else {
    for (float& value : values) {
      if (!(in >> value)) fail(path, "truncated: the header declares " + std::to_string(vertexCount) + " vertices");
    }
  }

  auto property = [&](std::size_t vertex, const char* name, float fallback) {
    const auto found = column.find(name);
    return found == column.end() ? fallback : values[vertex * properties.size() + found->second];
  };
  PointCache points;
  for (std::size_t v = 0; v < vertexCount; ++v) {
    points.positionsM.emplace_back(property(v, "x", 0), property(v, "y", 0), property(v, "z", 0));
    points.velocitiesMPerS.emplace_back(property(v, "vx", 0), property(v, "vy", 0), property(v, "vz", 0));
    points.massesKg.push_back(property(v, "mass", 0));
    points.plasticJ.push_back(property(v, "plastic_j", 1));
  }
  return points;
}

}  // namespace firn
