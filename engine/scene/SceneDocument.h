#pragma once
// A scene file as an editor holds it (docs/scene-format.md; the scene editor's model): its JSON as written, keys in
// the file's order, changed by edits that can be undone and redone, checked by the scene loader itself (the same
// rules and messages as `firn run`), and saved so that Firn loads the saved file to the same scene: keys no edit
// touched keep their values and their places.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "scene/JsonChecker.h"
#include "scene/Scene.h"

namespace firn {

class SceneDocument {
 public:
  // Reads `path` and checks it as loadScene does; throws InputError as loadScene does.
  static SceneDocument open(const std::filesystem::path& path);
  // A new scene to be saved at `path`, which does not exist yet: `text`'s (a built-in scene's), not saved.
  static SceneDocument create(const std::string& text, const std::filesystem::path& path);
  // The document of `text`, as if read from `path` (paths inside it are relative to its folder). Throws InputError
  // for text that is not a JSON object; a scene the loader refuses is a document with a problem().
  SceneDocument(const std::string& text, std::filesystem::path path);

  const json::Json& json() const { return json_; }
  const std::filesystem::path& path() const { return path_; }

  // One edit each, which undo() takes back whole. `pointer` is a JSON pointer ("/bodies/0/radius").
  // The value at `pointer` becomes `value`: an object's key that is not there is added after its last key, an array
  // index one past the end appends. Throws std::invalid_argument for a malformed pointer or one whose parent is not
  // there (as remove and insert do).
  void set(const std::string& pointer, json::Json value);
  // Removes an object's key, or an array's element (those after it move up).
  void remove(const std::string& pointer);
  // Adds `value` to the array at `pointer` before index `index` (the elements from there move down).
  void insert(const std::string& pointer, std::size_t index, json::Json value);
  bool canUndo() const { return done_ > 0; }
  bool canRedo() const { return done_ < edits_.size(); }
  void undo();
  void redo();
  // Whether the document differs from the file it was opened from or last saved to.
  bool modified() const { return done_ != savedAt_; }

  // What the loader says of the document now: nothing, or its message ("<file>: bodies[1].radius: must be greater
  // than 0 (got -0.1)") and the key path it names ("bodies[1].radius"; empty where it names none), which an editor
  // shows beside that key.
  struct Problem {
    std::string keyPath;
    std::string message;
  };
  std::optional<Problem> problem() const;
  // The scene as the loader reads the document; throws InputError as problem() says.
  Scene scene() const;
  // Both in one reading: the scene, or nothing and the problem.
  std::optional<Scene> sceneOrProblem(std::optional<Problem>& problem) const;

  // The keys the scene format allows in the object at `pointer` ("/grid", "/bodies/0"), as the loader lists them
  // when it meets a key it does not know: asked by reading the document with one such key added there. Empty where the
  // loader names none — the object's keys are names (materials), or the document has another problem first.
  std::vector<std::string> keysAllowedAt(const std::string& pointer) const;

  // The document as save() writes it: two-space indents, an array of numbers or strings on one line.
  std::string text() const;
  // Writes the document to `path` through a temporary file, its bodies', colliders' and rigid bodies' `path` keys
  // rewritten relative to the new folder, and makes `path` the document's; throws InputError, writing nothing,
  // while problem() finds one (a file Firn would refuse is no scene), or when the file cannot be written.
  void save(const std::filesystem::path& path);

 private:
  // An edit as what was at `pointer` before and what is after (none: no key or element there).
  struct Edit {
    std::string pointer;
    std::optional<json::Json> before;
    std::optional<json::Json> after;
    std::size_t keyPlace = 0;  // an object key's place among its siblings, for undoing its removal
  };
  void apply(const Edit& edit, bool forward);
  void record(Edit edit);

  json::Json json_;
  std::filesystem::path path_;
  std::vector<Edit> edits_;
  std::size_t done_ = 0;     // edits_[0, done_) are applied
  std::size_t savedAt_ = 0;  // done_ when opened or saved (never again reached once edits after it were dropped)
};

}  // namespace firn
