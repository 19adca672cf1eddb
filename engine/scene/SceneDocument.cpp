#include "scene/SceneDocument.h"

#include <cstring>
#include <limits>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "Error.h"
#include "io/AtomicFile.h"
#include "io/InputFile.h"

namespace firn {

namespace {

using Pointer = nlohmann::json_pointer<std::string>;

constexpr std::size_t kNever = std::numeric_limits<std::size_t>::max();

// A JSON pointer ("/bodies/0/radius"); a malformed one (no leading "/", a bad "~" escape) is an invalid argument.
Pointer pointerOf(const std::string& text) {
  try {
    return Pointer(text);
  } catch (const nlohmann::json::exception& error) {
    throw std::invalid_argument("\"" + text + "\": not a JSON pointer (" + error.what() + ")");
  }
}

// The container a pointer's last token names a member of, which must be there.
json::Json& parentOf(json::Json& root, const Pointer& pointer) {
  if (pointer.empty()) throw std::invalid_argument("an edit names the document itself, not a key in it");
  const Pointer parent = pointer.parent_pointer();
  if (!root.contains(parent)) throw std::invalid_argument(parent.to_string() + ": not in the document");
  json::Json& container = root[parent];
  if (!container.is_object() && !container.is_array()) {
    throw std::invalid_argument(parent.to_string() + ": neither an object nor an array");
  }
  return container;
}

std::size_t arrayIndex(const json::Json& array, const std::string& token) {
  if (token == "-") return array.size();
  if (token.empty() || token.find_first_not_of("0123456789") != std::string::npos) {
    throw std::invalid_argument("\"" + token + "\": not an array index");
  }
  return std::stoul(token);
}

std::size_t keyPlace(const json::Json& object, const std::string& key) {
  std::size_t place = 0;
  for (auto it = object.begin(); it != object.end(); ++it, ++place) {
    if (it.key() == key) return place;
  }
  return place;  // after the last
}

// `object` with `key` set to `value` at place `place` among its keys (an ordered map's entries cannot be moved).
void putKeyAt(json::Json& object, const std::string& key, json::Json value, std::size_t place) {
  if (object.contains(key)) {
    object[key] = std::move(value);
    return;
  }
  json::Json rebuilt = json::Json::object();
  std::size_t i = 0;
  for (auto it = object.begin(); it != object.end(); ++it, ++i) {
    if (i == place) rebuilt[key] = value;
    rebuilt[it.key()] = std::move(it.value());
  }
  if (!rebuilt.contains(key)) rebuilt[key] = std::move(value);
  object = std::move(rebuilt);
}

// A scalar, or an array of scalars (a vec3, cells, a hardening curve), fits on one line.
bool flat(const json::Json& value) {
  if (!value.is_array()) return !value.is_object();
  for (const json::Json& element : value) {
    if (element.is_array() || element.is_object()) return false;
  }
  return true;
}

void write(const json::Json& value, int indent, std::string& out) {
  const std::string inner(std::size_t(indent + 2), ' ');
  if (flat(value)) {
    if (!value.is_array()) {
      out += value.dump();
      return;
    }
    out += "[";
    for (std::size_t i = 0; i < value.size(); ++i) out += (i ? ", " : "") + value[i].dump();
    out += "]";
    return;
  }
  const bool object = value.is_object();
  if (value.empty()) {
    out += object ? "{}" : "[]";
    return;
  }
  out += object ? "{\n" : "[\n";
  std::size_t i = 0;
  for (auto it = value.begin(); it != value.end(); ++it, ++i) {
    out += inner;
    if (object) out += json::Json(it.key()).dump() + ": ";
    write(it.value(), indent + 2, out);
    out += i + 1 < value.size() ? ",\n" : "\n";
  }
  out += std::string(std::size_t(indent), ' ') + (object ? "}" : "]");
}

// The key path a loader's message names after "<file>: " ("bodies[1].radius"), or "".
std::string keyPathOf(const std::string& message, const std::string& file) {
  const std::string prefix = file + ": ";
  if (message.compare(0, prefix.size(), prefix) != 0) return "";
  const std::string rest = message.substr(prefix.size());
  const std::string candidate = rest.substr(0, rest.find(": "));
  static const std::regex keyPath(R"([a-z_]+(\[[0-9]+\])*(\.[a-z_0-9]+(\[[0-9]+\])*)*)");
  return std::regex_match(candidate, keyPath) ? candidate : "";
}

}  // namespace

SceneDocument SceneDocument::open(const std::filesystem::path& path) {
  SceneDocument document(readRegularFile(path, "scene file", kMaxSceneFileBytes), path);
  (void)document.scene();  // refused as loadScene refuses it
  return document;
}

SceneDocument SceneDocument::create(const std::string& text, const std::filesystem::path& path) {
  SceneDocument document(text, path);
  document.savedAt_ = kNever;  // no file holds it yet
  return document;
}

SceneDocument::SceneDocument(const std::string& text, std::filesystem::path path)
    : json_(json::parse(text, path.string())), path_(std::move(path)) {
  if (!json_.is_object()) throw InputError(path_.string() + ": a scene is a JSON object");
}

void SceneDocument::set(const std::string& pointer, json::Json value) {
  const Pointer at = pointerOf(pointer);
  json::Json& parent = parentOf(json_, at);
  Edit edit{pointer, std::nullopt, std::move(value)};
  if (parent.is_array()) {
    const std::size_t index = arrayIndex(parent, at.back());
    if (index > parent.size()) throw std::invalid_argument(pointer + ": past the array's end");
    edit.pointer = at.parent_pointer().to_string() + "/" + std::to_string(index);
    if (index < parent.size()) edit.before = parent[index];
  } else {
    if (parent.contains(at.back())) edit.before = parent[at.back()];
    edit.keyPlace = keyPlace(parent, at.back());
  }
  record(std::move(edit));
}

void SceneDocument::remove(const std::string& pointer) {
  const Pointer at = pointerOf(pointer);
  json::Json& parent = parentOf(json_, at);
  if (!json_.contains(at)) throw std::invalid_argument(pointer + ": not in the document");
  Edit edit{pointer, json_[at], std::nullopt};
  if (parent.is_object()) edit.keyPlace = keyPlace(parent, at.back());
  record(std::move(edit));
}

void SceneDocument::insert(const std::string& pointer, std::size_t index, json::Json value) {
  const Pointer at = pointerOf(pointer);
  if (!json_.contains(at) || !json_[at].is_array()) throw std::invalid_argument(pointer + ": not an array");
  if (index > json_[at].size()) throw std::invalid_argument(pointer + ": index past the array's end");
  record(Edit{pointer + "/" + std::to_string(index), std::nullopt, std::move(value)});
}

void SceneDocument::record(Edit edit) {
  edits_.resize(done_);  // what was undone is no longer redone
  if (savedAt_ > done_) savedAt_ = kNever;
  apply(edit, true);
  edits_.push_back(std::move(edit));
  ++done_;
}

void SceneDocument::undo() {
  if (!canUndo()) return;
  apply(edits_[--done_], false);
}

void SceneDocument::redo() {
  if (!canRedo()) return;
  apply(edits_[done_++], true);
}

void SceneDocument::apply(const Edit& edit, bool forward) {
  const Pointer at = pointerOf(edit.pointer);
  json::Json& parent = parentOf(json_, at);
  const std::optional<json::Json>& from = forward ? edit.before : edit.after;
  const std::optional<json::Json>& to = forward ? edit.after : edit.before;
  if (parent.is_array()) {
    const std::size_t index = arrayIndex(parent, at.back());
    if (from && to) {
      parent[index] = *to;
    } else if (to) {
      parent.insert(parent.begin() + std::ptrdiff_t(index), *to);
    } else {
      parent.erase(index);
    }
  } else if (to) {
    putKeyAt(parent, at.back(), *to, edit.keyPlace);
  } else {
    parent.erase(at.back());
  }
}

std::optional<Scene> SceneDocument::sceneOrProblem(std::optional<Problem>& problem) const {
  problem.reset();
  try {
    return scene();
  } catch (const InputError& error) {
    problem = Problem{keyPathOf(error.what(), path_.string()), error.what()};
  }
  return std::nullopt;
}

std::optional<SceneDocument::Problem> SceneDocument::problem() const {
  std::optional<Problem> found;
  (void)sceneOrProblem(found);
  return found;
}

Scene SceneDocument::scene() const { return parseScene(json_.dump(), path_); }

std::vector<std::string> SceneDocument::keysAllowedAt(const std::string& pointer) const {
  const Pointer at = pointerOf(pointer);
  if (!json_.contains(at) || !json_[at].is_object()) return {};
  // A key no scene uses: the loader's "unknown key (… allowed in WHAT: a, b, c)" lists the rest.
  constexpr const char* kProbe = "firn_editor_probe";
  json::Json probed = json_;
  probed[at][kProbe] = 0;
  try {
    (void)parseScene(probed.dump(), path_);
  } catch (const InputError& error) {
    const std::string message = error.what();
    const std::string named = keyPathOf(message, path_.string());
    if (named.size() < std::strlen(kProbe) || named.compare(named.size() - std::strlen(kProbe), std::string::npos,
                                                             kProbe) != 0) {
      return {};
    }
    const std::size_t allowed = message.find("allowed in ");
    const std::size_t list = allowed == std::string::npos ? allowed : message.find(": ", allowed);
    const std::size_t end = message.rfind(')');
    if (list == std::string::npos || end == std::string::npos || end < list) return {};
    std::vector<std::string> keys;
    std::istringstream names(message.substr(list + 2, end - list - 2));
    for (std::string name; std::getline(names, name, ',');) {
      name.erase(0, name.find_first_not_of(' '));
      if (!name.empty()) keys.push_back(name);
    }
    return keys;
  }
  return {};
}

std::string SceneDocument::text() const {
  std::string out;
  write(json_, 0, out);
  return out + "\n";
}

void SceneDocument::save(const std::filesystem::path& path) {
  if (const std::optional<Problem> found = problem()) throw InputError(found->message);
  const std::filesystem::path from = std::filesystem::absolute(path_).parent_path();
  const std::filesystem::path to = std::filesystem::absolute(path).parent_path();
  json::Json saved = json_;
  if (from.lexically_normal() != to.lexically_normal()) {
    for (const char* section : {"bodies", "colliders", "rigid_bodies"}) {
      if (!saved.contains(section)) continue;
      for (json::Json& entry : saved[section]) {
        if (!entry.is_object() || !entry.contains("path") || !entry["path"].is_string()) continue;
        const std::filesystem::path file = entry["path"].get<std::string>();
        if (file.is_absolute()) continue;
        const std::filesystem::path there = (from / file).lexically_normal();
        const std::filesystem::path relative = there.lexically_relative(to.lexically_normal());
        entry["path"] = (relative.empty() ? there : relative).generic_string();
      }
    }
  }
  std::swap(json_, saved);
  try {
    writeFileAtomically(path, text(), "scene file");
  } catch (...) {
    std::swap(json_, saved);  // nothing written: the document stays as it was
    throw;
  }
  path_ = path;
  savedAt_ = done_;
}

}  // namespace firn
