#include "io/Ply.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "Error.h"
#include "io/AtomicFile.h"
#include "io/InputFile.h"

namespace firn {

namespace {

const char* const kPropertyNames[] = {"x", "y", "z", "vx", "vy", "vz", "mass", "plastic_j"};
constexpr std::size_t kPropertyCount = sizeof kPropertyNames / sizeof kPropertyNames[0];

void appendLittleEndian(std::string& out, float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (int byte = 0; byte < 4; ++byte) out.push_back(static_cast<char>((bits >> (8 * byte)) & 0xFFu));
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
  writeFileAtomically(path, data, "point cache");
}

namespace {

// PLY's scalar types (both the original names and the sized aliases), as read into a double.
struct PlyType {
  const char* name;
  const char* alias;
  std::size_t bytes;
  double (*decode)(const unsigned char* bytes);
};

template <class T>
double decodeLittleEndian(const unsigned char* bytes) {
  std::uint64_t bits = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) bits |= std::uint64_t(bytes[i]) << (8 * i);
  T value;
  if constexpr (sizeof(T) == 8) {
    std::memcpy(&value, &bits, sizeof value);
  } else {
    using Unsigned = std::conditional_t<sizeof(T) == 4, std::uint32_t,
                                        std::conditional_t<sizeof(T) == 2, std::uint16_t, std::uint8_t>>;
    const auto narrow = static_cast<Unsigned>(bits);
    std::memcpy(&value, &narrow, sizeof value);
  }
  return static_cast<double>(value);
}

const PlyType kPlyTypes[] = {
    {"char", "int8", 1, decodeLittleEndian<std::int8_t>},       {"uchar", "uint8", 1, decodeLittleEndian<std::uint8_t>},
    {"short", "int16", 2, decodeLittleEndian<std::int16_t>},    {"ushort", "uint16", 2, decodeLittleEndian<std::uint16_t>},
    {"int", "int32", 4, decodeLittleEndian<std::int32_t>},      {"uint", "uint32", 4, decodeLittleEndian<std::uint32_t>},
    {"float", "float32", 4, decodeLittleEndian<float>},         {"double", "float64", 8, decodeLittleEndian<double>},
};

const PlyType* findPlyType(const std::string& name) {
  for (const PlyType& type : kPlyTypes) {
    if (name == type.name || name == type.alias) return &type;
  }
  return nullptr;
}

}  // namespace

PointCache readPly(const std::filesystem::path& path) {
  requireRegularFile(path, "point cache");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, std::string("cannot open point cache (") + std::strerror(errno) + ")");
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "ply") fail(path, "not a PLY file (first line is not \"ply\")");

  bool binary = false;
  std::size_t vertexCount = 0;
  bool inVertexElement = false;
  struct Property {
    std::string name;
    const PlyType* type;
  };
  std::vector<Property> properties;
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
      if (type == "list") fail(path, "list properties of vertices are not supported");
      const PlyType* known = findPlyType(type);
      if (known == nullptr) fail(path, "vertex property \"" + name + "\" has unknown type \"" + type + "\"");
      properties.push_back({name, known});
    } else if (keyword == "end_header") {
      break;
    }
  }
  if (line != "end_header") fail(path, "PLY header has no end_header");
  std::map<std::string, std::size_t> column;
  for (std::size_t i = 0; i < properties.size(); ++i) column[properties[i].name] = i;
  for (const char* required : {"x", "y", "z"}) {
    if (column.count(required) == 0) fail(path, std::string("vertex property \"") + required + "\" is missing");
  }

  // The header's vertex count is checked against the file before anything is allocated for it: a corrupt or
  // hostile count must be bad input, not an allocation failure. Binary records have a known size; an ASCII
  // value takes at least two bytes (a digit and a separator).
  std::error_code sizeError;
  const auto fileBytes = std::filesystem::file_size(path, sizeError);
  std::size_t recordBytes = 0;
  for (const Property& property : properties) recordBytes += binary ? property.type->bytes : 2;
  const auto headerBytes = static_cast<std::uintmax_t>(in.tellg());
  if (!sizeError && recordBytes > 0 &&
      vertexCount > (fileBytes > headerBytes ? fileBytes - headerBytes : 0) / recordBytes) {
    fail(path, "truncated: the header declares " + std::to_string(vertexCount) + " vertices, more than the file's " +
                   std::to_string(fileBytes) + " bytes can hold");
  }
  // Elements after the vertices (faces of a mesh, say) are not read: a point cloud is its vertices.
  std::vector<double> values(vertexCount * properties.size());
  const auto truncated = [&] { fail(path, "truncated: the header declares " + std::to_string(vertexCount) + " vertices"); };
  if (binary) {
    std::vector<unsigned char> record(recordBytes);
    for (std::size_t v = 0; v < vertexCount; ++v) {
      in.read(reinterpret_cast<char*>(record.data()), static_cast<std::streamsize>(recordBytes));
      if (static_cast<std::size_t>(in.gcount()) != recordBytes) truncated();
      const unsigned char* field = record.data();
      for (std::size_t p = 0; p < properties.size(); ++p) {
        values[v * properties.size() + p] = properties[p].type->decode(field);
        field += properties[p].type->bytes;
      }
    }
  } else {
    for (double& value : values) {
      if (!(in >> value)) truncated();
    }
  }

  auto property = [&](std::size_t vertex, const char* name, float fallback) {
    const auto found = column.find(name);
    return found == column.end() ? fallback : float(values[vertex * properties.size() + found->second]);
  };
  PointCache points;
  points.hasMass = column.count("mass") != 0;
  for (std::size_t v = 0; v < vertexCount; ++v) {
    points.positionsM.emplace_back(property(v, "x", 0), property(v, "y", 0), property(v, "z", 0));
    points.velocitiesMPerS.emplace_back(property(v, "vx", 0), property(v, "vy", 0), property(v, "vz", 0));
    points.massesKg.push_back(property(v, "mass", 0));
    points.plasticJ.push_back(property(v, "plastic_j", 1));
  }
  return points;
}

}  // namespace firn
