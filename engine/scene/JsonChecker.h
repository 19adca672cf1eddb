#pragma once
// Checked reading of a JSON document, for the scene loader. Every problem is an InputError of the form
// "<file>: <key path>: <problem>", e.g. "scenes/a.json: bodies[1].radius: must be greater than 0 (got -0.1)",
// so that a user can go straight to the offending key. The keys and values allowed are the callers' to say.
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "io/Text.h"

namespace firn::json {

// Ordered so that objects keep the order in which the file lists their keys (a scene's materials).
using Json = nlohmann::ordered_json;

// Arrays and objects within each other, at most (docs/scene-format.md, Sizes and limits): a scene nests 4 deep.
constexpr int kMaxNestingDepth = 64;

// Parses `text`, with `file` naming it in messages; a syntax error, a number beyond a double, a key set twice in
// one object or a nest deeper than kMaxNestingDepth is an InputError that gives the position or key path.
Json parse(const std::string& text, const std::string& file);

// "[x, y, z]", each to six significant digits.
std::string describePoint(const glm::dvec3& point);
std::string joinNames(const std::vector<std::string>& names);
// What a wrong value was, short enough for one line of an error message.
std::string describeValue(const Json& value);

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
  std::string describe() const;
};

template <class Enum>
using Choices = std::initializer_list<std::pair<const char*, Enum>>;

// One JSON value and the key path that leads to it; reads it as a checked number, string, enum or vector.
class Value {
 public:
  Value(const Json& json, std::string path, const std::string& file)
      : json_(json), path_(std::move(path)), file_(file) {}

  const Json& json() const { return json_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& problem) const;

  std::string pathOf(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  Value member(const std::string& key) const { return Value(json_.at(key), pathOf(key), file_); }
  Value element(std::size_t index) const {
    return Value(json_.at(index), path_ + "[" + std::to_string(index) + "]", file_);
  }

  double number(const Interval& allowed = Interval::any()) const;
  int integer(int low, int high) const;
  std::string string() const;
  glm::dvec3 vec3() const;
  glm::ivec3 ivec3(int low, int high) const;

  template <class Enum>
  Enum choice(Choices<Enum> choices) const {
    const std::string text = string();
    std::vector<std::string> supported;
    for (const auto& [name, value] : choices) {
      if (text == name) return value;
      supported.push_back(name);
    }
    failChoice(supported);
  }

 private:
  [[noreturn]] void failChoice(const std::vector<std::string>& supported) const;

  const Json& json_;
  std::string path_;
  const std::string& file_;
};

// A JSON object: required and optional members, and the check that it holds no key it should not.
class Object {
 public:
  explicit Object(const Value& value);

  const Value& value() const { return value_; }
  bool has(const std::string& key) const { return value_.json().contains(key); }

  // Fails at `key`, which need not be present ("required key is missing").
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

  Value required(const std::string& key) const;
  std::optional<Value> optional(const std::string& key) const;

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
  Enum choice(const std::string& key, Enum fallback, Choices<Enum> choices) const {
    return has(key) ? value_.member(key).template choice<Enum>(choices) : fallback;
  }

  // Unknown keys are errors (docs/scene-format.md), so that a misspelt key cannot silently fall back to a
  // default. `what` says which kind of object this is, since the allowed keys depend on it ("a sphere body").
  void checkKeys(const std::vector<std::string>& allowed, const std::string& what) const;

 private:
  Value value_;
};

}  // namespace firn::json
