// Reads design.md's scene file into a Scene. Every problem is an InputError of the form
// "<file>: <key path>: <problem>", e.g. "scenes/a.json: bodies[1].radius: must be greater than 0 (got -0.1)",
// so that a user can go straight to the offending key.
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <nlohmann/json.hpp>

#include "Error.h"
#include "io/PointCloud.h"
#include "scene/Scene.h"
#include "voxelizer/Mesh.h"

namespace firn {
namespace {

// Ordered so that materials keep the order in which the file lists them.
using Json = nlohmann::ordered_json;

// Shortest text that reads back as the same double ("0.1", not "0.10000000000000001").
std::string formatNumber(double value) {
  char text[32];
  const auto result = std::to_chars(std::begin(text), std::end(text), value);
  return std::string(text, result.ptr);
}

// Six significant digits, for values the loader derives (bounds, one frame's duration), where the last bits
// of a sum like 0.8 - 0.2 = 0.6000000000000001 are noise to the reader.
std::string formatApproximately(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

// What a wrong value was, short enough for one line of an error message.
std::string describeValue(const Json& value) {
  constexpr std::size_t maxChars = 40;
  switch (value.type()) {
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return "an array of " + std::to_string(value.size());
    case Json::value_t::string: {
      const std::string text = value.dump();
      return text.size() <= maxChars ? text : text.substr(0, maxChars) + "...\"";
    }
    default: return value.dump();
  }
}

// Levenshtein distance, to suggest the key a typo meant.
std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> previousRow(b.size() + 1), row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previousRow[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previousRow[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({previousRow[j] + 1, row[j - 1] + 1, substitution});
    }
    std::swap(previousRow, row);
  }
  return previousRow[b.size()];
}

// The range a number must lie in, open or closed at either end.
struct Interval {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool includesLow = true;
  bool includesHigh = true;

  static Interval any() { return {}; }
  static Interval greaterThan(double low) { return {low, std::numeric_limits<double>::infinity(), false, true}; }
  static Interval atLeast(double low) { return {low, std::numeric_limits<double>::infinity(), true, true}; }
  static Interval closed(double low, double high) { return {low, high, true, true}; }
  static Interval closedOpen(double low, double high) { return {low, high, true, false}; }
  static Interval openClosed(double low, double high) { return {low, high, false, true}; }

  bool contains(double value) const {
    return (includesLow ? value >= low : value > low) && (includesHigh ? value <= high : value < high);
  }
  std::string describe() const {
    if (std::isinf(high)) return (includesLow ? "at least " : "greater than ") + formatNumber(low);
    return std::string("in ") + (includesLow ? "[" : "(") + formatNumber(low) + ", " + formatNumber(high) +
           (includesHigh ? "]" : ")");
  }
};

template <class Enum>
using Choices = std::initializer_list<std::pair<const char*, Enum>>;
using Names = std::initializer_list<const char*>;

std::string notYetSupported(const std::string& what, const std::string& supported) {
  return what + " part of the scene format but not supported by this build yet" +
         (supported.empty() ? "" : " (supported: " + supported + ")");
}

// One JSON value and the key path that leads to it; reads it as a checked number, string, enum or vector.
class Value {
 public:
  Value(const Json& json, std::string path, const std::string& file)
      : json_(json), path_(std::move(path)), file_(file) {}

  const Json& json() const { return json_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(file_ + ": " + (path_.empty() ? "" : path_ + ": ") + problem);
  }

  std::string pathOf(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  Value member(const std::string& key) const { return Value(json_.at(key), pathOf(key), file_); }
  Value element(std::size_t index) const {
    return Value(json_.at(index), path_ + "[" + std::to_string(index) + "]", file_);
  }

  double number(const Interval& allowed = Interval::any()) const {
    if (!json_.is_number()) fail("expected a number (got " + describeValue(json_) + ")");
    // Finite by construction: JSON has no NaN or infinity, and parseScene rejects literals beyond a double.
    const double value = json_.get<double>();
    if (!allowed.contains(value)) fail("must be " + allowed.describe() + " (got " + json_.dump() + ")");
    return value;
  }

  int integer(int low, int high) const {
    if (!json_.is_number()) fail("expected an integer (got " + describeValue(json_) + ")");
    const double value = number();
    if (value != std::floor(value)) fail("expected an integer (got " + json_.dump() + ")");
    if (value < low || value > high) {
      fail("must be in [" + std::to_string(low) + ", " + std::to_string(high) + "] (got " + json_.dump() + ")");
    }
    return static_cast<int>(value);
  }

  std::string string() const {
    if (!json_.is_string()) fail("expected a string (got " + describeValue(json_) + ")");
    return json_.get<std::string>();
  }

  // `later` names values the scene format defines but this build does not implement yet.
  template <class Enum>
  Enum choice(Choices<Enum> choices, Names later = {}) const {
    const std::string text = string();
    std::vector<std::string> supported;
    for (const auto& [name, value] : choices) {
      if (text == name) return value;
      supported.push_back(name);
    }
    for (const char* name : later) {
      if (text == name) fail(notYetSupported("\"" + text + "\" is", joinNames(supported)));
    }
    std::vector<std::string> quoted;
    for (const std::string& name : supported) quoted.push_back("\"" + name + "\"");
    fail("must be one of " + joinNames(quoted) + " (got " + describeValue(json_) + ")");
  }

  glm::dvec3 vec3() const {
    if (!json_.is_array() || json_.size() != 3) {
      fail("expected an array of 3 numbers (got " + describeValue(json_) + ")");
    }
    return {element(0).number(), element(1).number(), element(2).number()};
  }

  glm::ivec3 ivec3(int low, int high) const {
    if (!json_.is_array() || json_.size() != 3) {
      fail("expected an array of 3 integers (got " + describeValue(json_) + ")");
    }
    return {element(0).integer(low, high), element(1).integer(low, high), element(2).integer(low, high)};
  }

 private:
  const Json& json_;
  std::string path_;
  const std::string& file_;
};

// A JSON object: required and optional members, and the check that it holds no key it should not.
class Object {
 public:
  explicit Object(const Value& value) : value_(value) {
    if (!value.json().is_object()) value.fail("expected an object (got " + describeValue(value.json()) + ")");
  }

  const Value& value() const { return value_; }
  bool has(const std::string& key) const { return value_.json().contains(key); }

  // Fails at `key`, which need not be present ("required key is missing").
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    Value(value_.json(), value_.pathOf(key), value_.file()).fail(problem);
  }

  Value required(const std::string& key) const {
    if (!has(key)) fail(key, "required key is missing");
    return value_.member(key);
  }
  std::optional<Value> optional(const std::string& key) const {
    if (!has(key)) return std::nullopt;
    return value_.member(key);
  }

  double number(const std::string& key, const Interval& allowed) const { return required(key).number(allowed); }
  double number(const std::string& key, double fallback, const Interval& allowed) const {
    return has(key) ? value_.member(key).number(allowed) : fallback;
  }
  int integer(const std::string& key, int fallback, int low, int high) const {
    return has(key) ? value_.member(key).integer(low, high) : fallback;
  }
  std::string string(const std::string& key, const std::string& fallback) const {
    return has(key) ? value_.member(key).string() : fallback;
  }
  glm::dvec3 vec3(const std::string& key) const { return required(key).vec3(); }
  glm::dvec3 vec3(const std::string& key, const glm::dvec3& fallback) const {
    return has(key) ? value_.member(key).vec3() : fallback;
  }
  template <class Enum>
  Enum choice(const std::string& key, Enum fallback, Choices<Enum> choices, Names later = {}) const {
    return has(key) ? value_.member(key).template choice<Enum>(choices, later) : fallback;
  }

  // Unknown keys are errors (design.md), so that a misspelt key cannot silently fall back to a default.
  // `later` names keys the scene format defines but this build does not implement yet; `what` says which
  // kind of object this is, since the allowed keys depend on it ("a sphere body").
  void checkKeys(const std::vector<std::string>& allowed, Names later, const std::string& what) const {
    for (const auto& member : value_.json().items()) {
      const std::string& key = member.key();
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      if (std::find(later.begin(), later.end(), key) != later.end()) fail(key, notYetSupported("this key is", ""));
      std::string suggestion;
      std::size_t closestDistance = 3;  // further than two edits is a different word, not a typo
      for (const std::string& candidate : allowed) {
        const std::size_t distance = editDistance(key, candidate);
        if (distance < closestDistance) {
          closestDistance = distance;
          suggestion = "did you mean \"" + candidate + "\"? ";
        }
      }
      fail(key, "unknown key (" + suggestion + "allowed in " + what + ": " + joinNames(allowed) + ")");
    }
  }

 private:
  Value value_;
};

// nlohmann keeps the last of two equal keys in an object; a scene that sets a key twice almost always has a
// stale copy, so it is reported instead. Tracks the key path while parsing to say where.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(const std::string& file) : file_(file) {}

  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start:
        countArrayElement();
        open_.push_back({event == Json::parse_event_t::array_start, 0, "", {}});
        break;
      case Json::parse_event_t::key: {
        Container& object = open_.back();
        object.currentKey = parsed.get<std::string>();
        if (!object.keys.insert(object.currentKey).second) {
          throw InputError(file_ + ": " + path() + ": duplicate key (an object may set each key once)");
        }
        break;
      }
      case Json::parse_event_t::value: countArrayElement(); break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end: open_.pop_back(); break;
    }
    return true;
  }

 private:
  struct Container {
    bool isArray;
    std::size_t elementsSeen;
    std::string currentKey;
    std::set<std::string> keys;
  };

  void countArrayElement() {
    if (!open_.empty() && open_.back().isArray) ++open_.back().elementsSeen;
  }
  std::string path() const {
    std::string text;
    for (const Container& container : open_) {
      if (container.isArray) {
        text += "[" + std::to_string(container.elementsSeen - 1) + "]";
      } else {
        text += (text.empty() ? "" : ".") + container.currentKey;
      }
    }
    return text;
  }

  const std::string& file_;
  std::vector<Container> open_;
};

// "line L, column C" of a 0-based byte offset into the text.
std::string describePosition(const std::string& text, std::size_t offset) {
  offset = std::min(offset, text.size());
  const std::size_t line = 1 + std::count(text.begin(), text.begin() + offset, '\n');
  const std::size_t lineStart = offset == 0 ? std::string::npos : text.rfind('\n', offset - 1);
  const std::size_t column = lineStart == std::string::npos ? offset + 1 : offset - lineStart;
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// nlohmann's messages read "[json.exception.<kind>.<id>] <text>"; the text is what a user needs.
std::string nlohmannText(const std::string& what) {
  const std::size_t idEnd = what.find("] ");
  return idEnd == std::string::npos ? what : what.substr(idEnd + 2);
}

// "<file>: line L, column C: JSON syntax error: ...", from nlohmann's byte offset.
[[noreturn]] void throwSyntaxError(const std::string& file, const std::string& text,
                                   const Json::parse_error& error) {
  // error.byte is the 1-based offset of the character the parser stopped at.
  const std::size_t offset = error.byte == 0 ? 0 : error.byte - 1;
  // Drop nlohmann's own "parse error at line L, column C: ", since the position is restated in front.
  std::string detail = nlohmannText(error.what());
  const std::size_t positionEnd = detail.find(": ");
  if (detail.rfind("parse error", 0) == 0 && positionEnd != std::string::npos) detail = detail.substr(positionEnd + 2);
  throw InputError(file + ": " + describePosition(text, offset) + ": JSON syntax error: " + detail);
}

// nlohmann refuses a number literal beyond the range of a double ("number overflow parsing '1e999'") without
// saying where; the literal it quotes is found in the text to give the position.
[[noreturn]] void throwNumberOverflow(const std::string& file, const std::string& text,
                                      const Json::out_of_range& error) {
  const std::string detail = nlohmannText(error.what());
  const std::size_t literalStart = detail.find('\'');
  const std::size_t literalEnd = detail.rfind('\'');
  std::string position;
  if (literalStart != std::string::npos && literalEnd > literalStart) {
    const std::size_t offset = text.find(detail.substr(literalStart + 1, literalEnd - literalStart - 1));
    if (offset != std::string::npos) position = describePosition(text, offset) + ": ";
  }
  throw InputError(file + ": " + position + detail + " (numbers must fit a double)");
}

GridSpec readGrid(const Object& grid) {
  grid.checkKeys({"origin", "cells", "cell_size"}, {}, "\"grid\"");
  GridSpec spec;
  spec.originM = grid.vec3("origin", spec.originM);
  // Fewer than 8 cells leaves at most 4 interior cells between the walls; 1024³ cells is already 10⁹ nodes.
  spec.cells = grid.required("cells").ivec3(8, 1024);
  // A cell over a kilometre is a unit mistake, and bounds the domain's extent far from a double's range.
  spec.cellSizeM = grid.number("cell_size", Interval::openClosed(0, 1000));
  return spec;
}

TimeSpec readTime(const Object& time) {
  time.checkKeys({"dt", "frame_rate", "frames", "adaptive", "cfl"}, {}, "\"time\"");
  TimeSpec spec;
  spec.frameRateHz = time.number("frame_rate", spec.frameRateHz, Interval::greaterThan(0));
  const double frameDurationS = 1.0 / spec.frameRateHz;
  spec.dtS = time.number("dt", Interval::greaterThan(0));
  if (spec.dtS > frameDurationS) {
    time.fail("dt", "must not exceed one frame, 1 / frame_rate = " + formatApproximately(frameDurationS) + " s (got " +
                        formatNumber(spec.dtS) + ")");
  }
  constexpr int maxFrames = 1000000;  // about nine hours at 30 Hz: more is a typo, not a shot
  spec.frames = time.integer("frames", spec.frames, 0, maxFrames);
  if (const auto adaptive = time.optional("adaptive")) {
    if (!adaptive->json().is_boolean()) adaptive->fail("expected true or false (got " + describeValue(adaptive->json()) + ")");
    spec.adaptive = adaptive->json().get<bool>();
  }
  if (time.has("cfl") && !spec.adaptive) time.fail("cfl", "applies only with \"adaptive\": true");
  // Beyond 1 the fastest particle, or the elastic wave, crosses more than a cell per step.
  spec.cfl = time.number("cfl", spec.cfl, Interval::openClosed(0, 1));
  return spec;
}

SolverSpec readSolver(const Object& solver) {
  solver.checkKeys({"kernel", "transfer", "flip_ratio", "atomics", "particle_volume"}, {}, "\"solver\"");
  SolverSpec spec;
  spec.kernel = solver.choice<Kernel>("kernel", spec.kernel, {{"quadratic", Kernel::Quadratic}, {"cubic", Kernel::Cubic}});
  spec.transfer =
      solver.choice<Transfer>("transfer", spec.transfer, {{"pic_flip", Transfer::PicFlip}, {"apic", Transfer::Apic}});
  spec.flipRatio = solver.number("flip_ratio", spec.flipRatio, Interval::closed(0, 1));
  spec.atomics =
      solver.choice<Atomics>("atomics", spec.atomics,
                             {{"fixed", Atomics::FixedPoint}, {"float", Atomics::Float}, {"none", Atomics::None}});
  spec.particleVolume = solver.choice<ParticleVolume>(
      "particle_volume", spec.particleVolume,
      {{"grid_density", ParticleVolume::GridDensity}, {"material_density", ParticleVolume::MaterialDensity}});
  return spec;
}

const Material* findPreset(const std::string& name) {
  for (const Material& preset : snowPresets()) {
    if (preset.name == name) return &preset;
  }
  return nullptr;
}

// Snow: a preset supplies every number and explicit keys override it; without one, all are required.
void readSnow(const Object& material, Material& result) {
  material.checkKeys({"model", "preset", "youngs_modulus", "poisson_ratio", "density", "critical_compression",
                      "critical_stretch", "hardening"},
                     {}, "a snow material");
  const bool hasPreset = material.has("preset");
  if (hasPreset) {
    const Value presetName = material.required("preset");
    const Material* preset = findPreset(presetName.string());
    if (preset == nullptr) {
      std::vector<std::string> names;
      for (const Material& known : snowPresets()) names.push_back(known.name);
      presetName.fail("unknown preset " + describeValue(presetName.json()) + " (presets: " + joinNames(names) + ")");
    }
    result = *preset;
  }
  const auto read = [&](const char* key, double& field, const Interval& allowed) {
    if (material.has(key)) {
      field = material.number(key, allowed);
    } else if (!hasPreset) {
      material.fail(key, "required key is missing (give it, or a \"preset\" that supplies it)");
    }
  };
  read("youngs_modulus", result.youngsModulusPa, Interval::greaterThan(0));
  // ν = 0.5 is incompressible: λ = Eν / ((1 + ν)(1 − 2ν)) diverges.
  read("poisson_ratio", result.poissonRatio, Interval::closedOpen(0, 0.5));
  read("density", result.densityKgPerM3, Interval::greaterThan(0));
  // θc = 1 would let a singular value be clamped to 0, a collapsed particle.
  read("critical_compression", result.criticalCompression, Interval::closedOpen(0, 1));
  read("critical_stretch", result.criticalStretch, Interval::atLeast(0));
  read("hardening", result.hardening, Interval::atLeast(0));
}

void readElasticConstants(const Object& material, Material& result) {
  result.youngsModulusPa = material.number("youngs_modulus", Interval::greaterThan(0));
  result.poissonRatio = material.number("poisson_ratio", Interval::closedOpen(0, 0.5));
  result.densityKgPerM3 = material.number("density", Interval::greaterThan(0));
}

// Sand: a constant friction angle, or Klár 2016's hardening [h0, h1, h2, h3] (degrees, degrees, 1, degrees)
// with h0 > h3 ≥ 0 and h1, h2 ≥ 0 (seed 001 §4.4.2); φ must stay below 90°, where the cone is a plane.
void readDruckerPrager(const Object& material, Material& result) {
  material.checkKeys({"model", "youngs_modulus", "poisson_ratio", "density", "friction_angle_deg", "hardening"}, {},
                     "a drucker_prager material");
  readElasticConstants(material, result);
  if (const auto hardening = material.optional("hardening")) {
    if (material.has("friction_angle_deg")) {
      material.fail("friction_angle_deg", "give either friction_angle_deg (a constant angle) or hardening "
                                          "[h0, h1, h2, h3] (an angle h0 + (h1 q − h3) e^{−h2 q} that grows with q), not both");
    }
    if (!hardening->json().is_array() || hardening->json().size() != 4) {
      hardening->fail("expected [h0, h1, h2, h3] (got " + describeValue(hardening->json()) + ")");
    }
    result.hardeningH0Deg = hardening->element(0).number(Interval::closedOpen(0, 90));
    result.hardeningH1Deg = hardening->element(1).number(Interval::atLeast(0));
    result.hardeningH2 = hardening->element(2).number(Interval::atLeast(0));
    result.hardeningH3Deg = hardening->element(3).number(Interval::closedOpen(0, result.hardeningH0Deg));
  } else {
    result.hardeningH0Deg = material.number("friction_angle_deg", Interval::closedOpen(0, 90));
    result.hardeningH1Deg = result.hardeningH2 = result.hardeningH3Deg = 0;
  }
}

Material readMaterial(const Object& material, const std::string& name) {
  Material result;
  // With a preset (snow) the model is implied; without one it must be said, since the keys depend on it.
  if (!material.has("preset") || material.has("model")) {
    result.model = material.required("model").choice<MaterialModel>({{"snow", MaterialModel::Snow},
                                                                      {"fixed_corotated", MaterialModel::FixedCorotated},
                                                                      {"neo_hookean", MaterialModel::NeoHookean},
                                                                      {"water", MaterialModel::Water},
                                                                      {"drucker_prager", MaterialModel::DruckerPrager}});
  }
  switch (result.model) {
    case MaterialModel::Snow: readSnow(material, result); break;
    case MaterialModel::FixedCorotated:
    case MaterialModel::NeoHookean:
      material.checkKeys({"model", "youngs_modulus", "poisson_ratio", "density"}, {},
                         result.model == MaterialModel::NeoHookean ? "a neo_hookean material" : "a fixed_corotated material");
      readElasticConstants(material, result);
      break;
    case MaterialModel::Water:
      material.checkKeys({"model", "density", "bulk_modulus", "gamma", "viscosity"}, {}, "a water material");
      result.densityKgPerM3 = material.number("density", Interval::greaterThan(0));
      result.bulkModulusPa = material.number("bulk_modulus", Interval::greaterThan(0));
      // γ ≥ 1: the pressure must stiffen as water compresses (seed 001 uses γ = 4 to 7).
      result.gamma = material.number("gamma", Interval::atLeast(1));
      result.viscosityPaS = material.number("viscosity", result.viscosityPaS, Interval::atLeast(0));
      break;
    case MaterialModel::DruckerPrager: readDruckerPrager(material, result); break;
  }
  result.name = name;
  return result;
}

std::vector<Material> readMaterials(const Object& materials) {
  std::vector<Material> result;
  for (const auto& member : materials.value().json().items()) {
    if (member.key().empty()) materials.value().fail("a material name must not be empty");
    result.push_back(readMaterial(Object(materials.value().member(member.key())), member.key()));
  }
  if (result.empty()) materials.value().fail("at least one material is required");
  return result;
}

std::string describePoint(const glm::dvec3& pointM) {
  return "[" + formatApproximately(pointM.x) + ", " + formatApproximately(pointM.y) + ", " +
         formatApproximately(pointM.z) + "]";
}

std::string describeBox(const glm::dvec3& minM, const glm::dvec3& maxM) {
  return describePoint(minM) + " to " + describePoint(maxM) + " m";
}

void checkBoxCorners(const Object& box, const glm::dvec3& minM, const glm::dvec3& maxM) {
  if (!glm::all(glm::lessThan(minM, maxM))) {
    box.fail("max", "must exceed \"min\" on every axis (min " + describePoint(minM) + ", max " + describePoint(maxM) + ")");
  }
}

int readMaterialReference(const Object& body, const std::vector<Material>& materials) {
  const Value reference = body.required("material");
  const std::string name = reference.string();
  std::vector<std::string> names;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].name == name) return static_cast<int>(i);
    names.push_back(materials[i].name);
  }
  reference.fail("no material named " + describeValue(reference.json()) + " (materials: " + joinNames(names) + ")");
}

voxelizer::Transform readPlacement(const Object& body) {
  voxelizer::Transform placement;
  placement.scale = body.number("scale", placement.scale, Interval::greaterThan(0));
  placement.rotateDeg = body.vec3("rotate_deg", placement.rotateDeg);
  placement.translateM = body.vec3("translate", placement.translateM);
  return placement;
}

void loadMeshBody(const Object& body, Body& result, const voxelizer::Transform& placement) {
  voxelizer::TriangleMesh mesh;
  try {
    mesh = voxelizer::transformed(voxelizer::loadMesh(result.resolvedPath), placement);
  } catch (const InputError& error) {
    body.fail("path", error.what());
  }
  const voxelizer::Bounds box = voxelizer::bounds(mesh);
  result.loadedMinM = box.minM;
  result.loadedMaxM = box.maxM;
  result.mesh = std::make_shared<const voxelizer::TriangleMesh>(std::move(mesh));
}

void loadPointsBody(const Object& body, Body& result, const voxelizer::Transform& placement, const GridSpec& grid,
                    double densityKgPerM3) {
  PointCloud cloud;
  try {
    cloud = readPointCloud(result.resolvedPath);
  } catch (const InputError& error) {
    body.fail("path", error.what());
  }
  const glm::dmat3 rotation = voxelizer::rotationMatrix(placement.rotateDeg);
  std::vector<glm::dvec3> points;
  points.reserve(cloud.positionsM.size());
  result.loadedMinM = glm::dvec3(std::numeric_limits<double>::infinity());
  result.loadedMaxM = -result.loadedMinM;
  for (const glm::dvec3& p : cloud.positionsM) {
    const glm::dvec3& placed = points.emplace_back(placement.translateM + rotation * (placement.scale * p));
    // A scale or translation near the limits of a double can carry a point to infinity (or NaN, ∞ − ∞).
    if (!std::isfinite(placed.x) || !std::isfinite(placed.y) || !std::isfinite(placed.z)) {
      body.value().fail("placing the cloud (scale, rotate_deg, translate) takes a point beyond the range of a double");
    }
    result.loadedMinM = glm::min(result.loadedMinM, placed);
    result.loadedMaxM = glm::max(result.loadedMaxM, placed);
  }
  result.pointSpacingM = medianNeighbourSpacingM(points);
  if (!std::isfinite(result.pointSpacingM)) {
    body.value().fail("the placed cloud's points are further apart than a double can measure");
  }
  if (result.pointSpacingM > 0) result.particlesPerCell = std::pow(grid.cellSizeM / result.pointSpacingM, 3.0);

  if (body.has("particle_mass")) {
    result.pointMassesKg = {body.number("particle_mass", Interval::greaterThan(0))};
  } else if (!cloud.massesKg.empty()) {
    // The file's masses belong to the cloud at its own size; scaled by s, it covers s³ the volume.
    const double volumeRatio = placement.scale * placement.scale * placement.scale;
    for (double massKg : cloud.massesKg) result.pointMassesKg.push_back(massKg * volumeRatio);
  } else if (result.pointSpacingM > 0) {
    result.pointMassesKg = {densityKgPerM3 * result.pointSpacingM * result.pointSpacingM * result.pointSpacingM};
  } else {
    body.fail("particle_mass", "required key is missing: the cloud's points coincide, so no spacing (and no mass "
                               "from the density) can be derived from it");
  }
  result.pointsM = std::make_shared<const std::vector<glm::dvec3>>(std::move(points));
}

// Masses live in 32-bit floats on the GPU: each must be a normal float, neither 0 nor infinite after rounding
// (extreme densities, spacings, scales or mass_scale can produce either).
void checkParticleMasses(const Object& body, const Body& result, const GridSpec& grid, const Material& material) {
  const auto check = [&](double massKg, const std::string& origin) {
    const double scaledKg = massKg * result.massScale;
    if (!(scaledKg >= double(std::numeric_limits<float>::min()) && scaledKg <= double(std::numeric_limits<float>::max()))) {
      body.value().fail("a particle's mass, " + formatApproximately(scaledKg) + " kg (" + origin +
                        "), is outside what the GPU's 32-bit floats hold; change the density, scale or mass_scale");
    }
  };
  if (result.shape == BodyShape::Points) {
    const auto [lightest, heaviest] = std::minmax_element(result.pointMassesKg.begin(), result.pointMassesKg.end());
    check(*lightest, "the lightest of the cloud's");
    check(*heaviest, "the heaviest of the cloud's");
    return;
  }
  const double spacingM = grid.cellSizeM / std::cbrt(result.particlesPerCell);
  check(material.densityKgPerM3 * spacingM * spacingM * spacingM, "density × spacing³ × mass_scale");
}

Body readBody(const Object& body, const GridSpec& grid, const std::vector<Material>& materials,
              const std::filesystem::path& sceneFolder) {
  Body result;
  result.shape = body.required("shape").choice<BodyShape>(
      {{"sphere", BodyShape::Sphere}, {"box", BodyShape::Box}, {"mesh", BodyShape::Mesh}, {"points", BodyShape::Points}});
  const auto keysWith = [](const std::vector<std::string>& shapeKeys) {
    std::vector<std::string> keys = {"shape"};
    keys.insert(keys.end(), shapeKeys.begin(), shapeKeys.end());
    for (const char* common : {"material", "velocity", "angular_velocity", "lambda_scale", "mu_scale", "mass_scale",
                               "start_frame", "duration_frames"}) {
      keys.push_back(common);
    }
    return keys;
  };
  const auto readFile = [&] {
    result.path = body.required("path").string();
    if (result.path.empty()) body.fail("path", "must not be empty");
    result.resolvedPath = sceneFolder / result.path;
  };
  switch (result.shape) {
    case BodyShape::Sphere:
      body.checkKeys(keysWith({"center", "radius", "particles_per_cell", "sampler"}), {}, "a sphere body");
      result.centerM = body.vec3("center");
      result.radiusM = body.number("radius", Interval::greaterThan(0));
      break;
    case BodyShape::Box:
      body.checkKeys(keysWith({"min", "max", "particles_per_cell", "sampler"}), {}, "a box body");
      result.minM = body.vec3("min");
      result.maxM = body.vec3("max");
      checkBoxCorners(body, result.minM, result.maxM);
      break;
    case BodyShape::Mesh:
      body.checkKeys(keysWith({"path", "scale", "rotate_deg", "translate", "particles_per_cell", "sampler"}), {},
                     "a mesh body");
      readFile();
      break;
    case BodyShape::Points:
      body.checkKeys(keysWith({"path", "scale", "rotate_deg", "translate", "particle_mass"}), {},
                     "a points body");
      readFile();
      break;
  }
  result.materialIndex = readMaterialReference(body, materials);
  result.velocityMPerS = body.vec3("velocity", result.velocityMPerS);
  result.angularVelocityRadPerS = body.vec3("angular_velocity", result.angularVelocityRadPerS);
  result.lambdaScale = body.number("lambda_scale", result.lambdaScale, Interval::atLeast(0));
  result.muScale = body.number("mu_scale", result.muScale, Interval::atLeast(0));
  result.massScale = body.number("mass_scale", result.massScale, Interval::greaterThan(0));
  constexpr int maxFrames = 1000000;  // as time.frames
  result.startFrame = body.integer("start_frame", result.startFrame, 0, maxFrames);
  result.durationFrames = body.integer("duration_frames", result.durationFrames, 0, maxFrames);
  result.particlesPerCell = body.number("particles_per_cell", result.particlesPerCell, Interval::openClosed(0, 1000));
  result.sampler = body.choice<BodySampler>("sampler", result.sampler,
                                            {{"lattice", BodySampler::Lattice}, {"poisson_disk", BodySampler::PoissonDisk}});
  if (result.shape == BodyShape::Mesh) loadMeshBody(body, result, readPlacement(body));
  if (result.shape == BodyShape::Points) {
    loadPointsBody(body, result, readPlacement(body), grid,
                   materials[std::size_t(result.materialIndex)].densityKgPerM3);
  }

  checkParticleMasses(body, result, grid, materials[std::size_t(result.materialIndex)]);

  // Particles must start clear of the wall cells, where the grid update zeroes the velocity.
  const glm::dvec3 interiorMinM = grid.interiorMinM();
  const glm::dvec3 interiorMaxM = grid.interiorMaxM();
  if (!glm::all(glm::greaterThanEqual(result.boundsMinM(), interiorMinM)) ||
      !glm::all(glm::lessThanEqual(result.boundsMaxM(), interiorMaxM))) {
    body.value().fail("the body reaches outside the simulation interior: its bounding box is " +
                      describeBox(result.boundsMinM(), result.boundsMaxM()) + ", the interior (the grid less " +
                      std::to_string(GridSpec::wallCells) + " wall cells on each side) is " +
                      describeBox(interiorMinM, interiorMaxM));
  }
  return result;
}

Collider readCollider(const Object& collider) {
  Collider result;
  result.shape = collider.required("type").choice<ColliderShape>(
      {{"plane", ColliderShape::Plane}, {"sphere", ColliderShape::Sphere}, {"box", ColliderShape::Box}}, {"mesh"});
  const std::vector<std::string> commonKeys = {"velocity", "friction", "boundary"};
  const auto keysWith = [&](std::vector<std::string> keys) {
    keys.insert(keys.end(), commonKeys.begin(), commonKeys.end());
    return keys;
  };
  switch (result.shape) {
    case ColliderShape::Plane: {
      collider.checkKeys(keysWith({"type", "point", "normal"}), {}, "a plane collider");
      result.pointM = collider.vec3("point");
      const glm::dvec3 normal = collider.vec3("normal");
      const double largestComponent = std::max({std::abs(normal.x), std::abs(normal.y), std::abs(normal.z)});
      if (largestComponent == 0) collider.fail("normal", "must not be the zero vector");
      // Scaled down first so that the length of a vector like [1e200, 0, 1e200] cannot overflow.
      result.normal = glm::normalize(normal / largestComponent);
      break;
    }
    case ColliderShape::Sphere:
      collider.checkKeys(keysWith({"type", "center", "radius"}), {}, "a sphere collider");
      result.centerM = collider.vec3("center");
      result.radiusM = collider.number("radius", Interval::greaterThan(0));
      break;
    case ColliderShape::Box:
      collider.checkKeys(keysWith({"type", "min", "max"}), {}, "a box collider");
      result.minM = collider.vec3("min");
      result.maxM = collider.vec3("max");
      checkBoxCorners(collider, result.minM, result.maxM);
      break;
  }
  result.velocityMPerS = collider.vec3("velocity", result.velocityMPerS);
  result.friction = collider.number("friction", result.friction, Interval::atLeast(0));
  result.boundary = collider.choice<Boundary>(
      "boundary", result.boundary,
      {{"sticky", Boundary::Sticky}, {"slip", Boundary::Slip}, {"separate", Boundary::Separate}});
  return result;
}

CameraSpec readCamera(const Object& camera) {
  camera.checkKeys({"position", "target", "fov_deg"}, {}, "\"camera\"");
  CameraSpec spec;
  spec.positionM = camera.vec3("position");
  spec.targetM = camera.vec3("target");
  if (spec.positionM == spec.targetM) camera.fail("target", "must differ from \"position\" (the camera looks from one to the other)");
  // Beyond 170° the perspective stretches everything to the corners; below 1° it is a telescope.
  spec.fovDeg = camera.number("fov_deg", spec.fovDeg, Interval::closed(1, 170));
  return spec;
}

Scene readScene(const Object& root, const std::filesystem::path& sceneFolder) {
  root.checkKeys(
      {"name", "description", "grid", "time", "gravity", "solver", "materials", "bodies", "colliders", "camera"}, {},
      "a scene");
  Scene scene;
  scene.name = root.string("name", scene.name);
  scene.description = root.string("description", scene.description);
  scene.grid = readGrid(Object(root.required("grid")));
  scene.time = readTime(Object(root.required("time")));
  scene.gravityMPerS2 = root.vec3("gravity", scene.gravityMPerS2);
  if (const auto solver = root.optional("solver")) scene.solver = readSolver(Object(*solver));
  scene.materials = readMaterials(Object(root.required("materials")));

  const Value bodies = root.required("bodies");
  if (!bodies.json().is_array()) bodies.fail("expected an array of bodies (got " + describeValue(bodies.json()) + ")");
  if (bodies.json().empty()) bodies.fail("at least one body is required");
  for (std::size_t i = 0; i < bodies.json().size(); ++i) {
    scene.bodies.push_back(readBody(Object(bodies.element(i)), scene.grid, scene.materials, sceneFolder));
  }

  if (const auto colliders = root.optional("colliders")) {
    if (!colliders->json().is_array()) {
      colliders->fail("expected an array of colliders (got " + describeValue(colliders->json()) + ")");
    }
    for (std::size_t i = 0; i < colliders->json().size(); ++i) {
      scene.colliders.push_back(readCollider(Object(colliders->element(i))));
    }
  }
  if (const auto camera = root.optional("camera")) scene.camera = readCamera(Object(*camera));
  return scene;
}

}  // namespace

Scene parseScene(const std::string& jsonText, const std::filesystem::path& source) {
  const std::string file = source.string();
  Json root;
  try {
    root = Json::parse(jsonText, DuplicateKeyCheck(file));
  } catch (const Json::parse_error& error) {
    throwSyntaxError(file, jsonText, error);
  } catch (const Json::out_of_range& error) {
    throwNumberOverflow(file, jsonText, error);
  }
  Scene scene = readScene(Object(Value(root, "", file)), source.parent_path());
  scene.sourcePath = source;
  return scene;
}

Scene loadScene(const std::filesystem::path& path) {
  const std::string file = path.string();
  const auto cannotOpen = [&](int errorNumber) {
    return InputError(file + ": cannot open scene file (" + std::strerror(errorNumber) + ")");
  };
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> stream(std::fopen(file.c_str(), "rb"), &std::fclose);
  if (!stream) throw cannotOpen(errno);
  std::string text;
  char buffer[1 << 16];
  std::size_t bytesRead;
  while ((bytesRead = std::fread(buffer, 1, sizeof buffer, stream.get())) > 0) text.append(buffer, bytesRead);
  // A directory opens on Linux and fails on the first read with EISDIR.
  if (std::ferror(stream.get())) throw cannotOpen(errno);
  return parseScene(text, path);
}

}  // namespace firn
