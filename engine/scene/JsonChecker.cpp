#include "scene/JsonChecker.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string_view>

#include "Error.h"

namespace firn::json {
namespace {

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

// Refuses arrays and objects nested deeper than kMaxNestingDepth before nlohmann sees the text: its parse through a
// callback recurses with the nesting (150 KB of balanced brackets overflowed the stack), as do its copies and
// dump(). One pass, no recursion; brackets inside strings do not count. Whatever else is wrong with the text is the
// parser's to say.
void checkNestingDepth(const std::string& text, const std::string& file) {
  int depth = 0;
  bool inString = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\') {
        ++i;  // the escaped character, a quote included
      } else if (c == '"') {
        inString = false;
      }
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNestingDepth) {
        throw InputError(file + ": " + describePosition(text, i) + ": arrays and objects nested more than " +
                         std::to_string(kMaxNestingDepth) + " levels deep (a scene's own keys go 4 levels deep)");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

}  // namespace

Json parse(const std::string& text, const std::string& file) {
  checkNestingDepth(text, file);
  try {
    return Json::parse(text, DuplicateKeyCheck(file));
  } catch (const Json::parse_error& error) {
    throwSyntaxError(file, text, error);
  } catch (const Json::out_of_range& error) {
    throwNumberOverflow(file, text, error);
  }
}

std::string describePoint(const glm::dvec3& point) {
  return "[" + formatApproximately(point.x) + ", " + formatApproximately(point.y) + ", " +
         formatApproximately(point.z) + "]";
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

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

std::string Interval::describe() const {
  if (std::isinf(high)) return (includesLow ? "at least " : "greater than ") + formatNumber(low);
  return std::string("in ") + (includesLow ? "[" : "(") + formatNumber(low) + ", " + formatNumber(high) +
         (includesHigh ? "]" : ")");
}

void Value::fail(const std::string& problem) const {
  throw InputError(file_ + ": " + (path_.empty() ? "" : path_ + ": ") + problem);
}

double Value::number(const Interval& allowed) const {
  if (!json_.is_number()) fail("expected a number (got " + describeValue(json_) + ")");
  // Finite by construction: JSON has no NaN or infinity, and parse() rejects literals beyond a double.
  const double value = json_.get<double>();
  if (!allowed.contains(value)) fail("must be " + allowed.describe() + " (got " + json_.dump() + ")");
  return value;
}

int Value::integer(int low, int high) const {
  if (!json_.is_number()) fail("expected an integer (got " + describeValue(json_) + ")");
  const double value = number();
  if (value != std::floor(value)) fail("expected an integer (got " + json_.dump() + ")");
  if (value < low || value > high) {
    fail("must be in [" + std::to_string(low) + ", " + std::to_string(high) + "] (got " + json_.dump() + ")");
  }
  return static_cast<int>(value);
}

std::string Value::string() const {
  if (!json_.is_string()) fail("expected a string (got " + describeValue(json_) + ")");
  return json_.get<std::string>();
}

void Value::failChoice(const std::vector<std::string>& supported) const {
  std::vector<std::string> quoted;
  for (const std::string& name : supported) quoted.push_back("\"" + name + "\"");
  fail("must be one of " + joinNames(quoted) + " (got " + describeValue(json_) + ")");
}

glm::dvec3 Value::vec3() const {
  if (!json_.is_array() || json_.size() != 3) {
    fail("expected an array of 3 numbers (got " + describeValue(json_) + ")");
  }
  return {element(0).number(), element(1).number(), element(2).number()};
}

glm::ivec3 Value::ivec3(int low, int high) const {
  if (!json_.is_array() || json_.size() != 3) {
    fail("expected an array of 3 integers (got " + describeValue(json_) + ")");
  }
  return {element(0).integer(low, high), element(1).integer(low, high), element(2).integer(low, high)};
}

Object::Object(const Value& value) : value_(value) {
  if (!value.json().is_object()) value.fail("expected an object (got " + describeValue(value.json()) + ")");
}

void Object::fail(const std::string& key, const std::string& problem) const {
  Value(value_.json(), value_.pathOf(key), value_.file()).fail(problem);
}

Value Object::required(const std::string& key) const {
  if (!has(key)) fail(key, "required key is missing");
  return value_.member(key);
}

std::optional<Value> Object::optional(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return value_.member(key);
}

void Object::checkKeys(const std::vector<std::string>& allowed, const std::string& what) const {
  for (const auto& member : value_.json().items()) {
    const std::string& key = member.key();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
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

}  // namespace firn::json
