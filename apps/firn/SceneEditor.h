#pragma once
// `firn view SCENE --edit`: the scene editor's panel (Dear ImGui) over a SceneDocument (scene/SceneDocument.h). It
// lists the scene's parts — grid, time, solver, materials, bodies and emitters, colliders with their keyframes, rigid
// bodies, camera — and edits every key of the file as the file writes it: each edit is one step of undo, the loader
// checks the result, and its message stands beside the key it names (and at the top) until the scene is one Firn
// runs. Beside them, the numbers the scene would start with (run/SimulationSession.h, numbersBeforeRunning): the
// particles each body makes and in all against the budget, the pre-flight's bounds on the step against time.dt, its
// warnings. The window (apps/firn/Viewer.cpp) draws the panel over the view and runs the scene it asks for.
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <imgui.h>

struct GLFWwindow;

#include "gl/Context.h"
#include "run/SimulationSession.h"
#include "scene/SceneDocument.h"

namespace firn {

class SceneEditor {
 public:
  // The numbers before running are `firn run`'s for the document (the window keeps room for its snowballs beside).
  SceneEditor(SceneDocument document, const gl::ContextInfo& gl);

  // What the user asked of the window in this frame.
  enum class Request { None, Run, Edit, Quit };
  // Draws the panel (between ImGui::NewFrame and ImGui::Render). `running`: the window is running the scene, not
  // editing it; the keys are left to the view while it runs, but for Tab (back to editing).
  Request draw(bool running);

  // The panel's width in the framebuffer's pixels: the view beside it starts there.
  static int panelWidthPx(GLFWwindow* window);

  const SceneDocument& document() const { return document_; }
  // The scene to run: the document's, when the loader and the numbers before running found no problem.
  std::optional<Scene> runnableScene() const;
  // The loader's or the pre-flight's message while the scene cannot run.
  std::optional<std::string> problemMessage() const;
  // The window asks to close: at once without unsaved changes (true), else after the user's answer in a dialog.
  bool closeRequested();

  // The centre of the field that edits `pointer` ("/materials/snow/youngs_modulus"), or of the part's heading, in
  // the last frame drawn, in the window's coordinates; nothing if it was not drawn. Scripted input clicks there.
  std::optional<ImVec2> fieldCentre(const std::string& pointer) const;
  // Whether the last frame drew that field at all, in view or scrolled out of it; reveal() scrolls it into view.
  bool drewField(const std::string& pointer) const { return lastFieldCentres_.count(pointer) > 0; }
  void reveal(const std::string& pointer) { reveal_ = pointer; }

 private:
  void drawToolbar(bool running, Request& request);
  void drawNumbers();
  void drawProblem();
  // `element`: the value is an element of an array (duplicated and deleted), else an object's key (removed).
  void drawValue(const std::string& pointer, const std::string& label, const json::Json& value, int depth,
                 bool element);
  void drawLeaf(const std::string& pointer, const json::Json& value);
  void drawArrayTools(const std::string& pointer, const json::Json& array);
  void drawAddKey(const std::string& pointer);
  void drawCloseDialog(Request& request);
  void showMessageAt(const std::string& pointer);
  void remember(const std::string& pointer);
  // Applies an edit through `change`, reporting a refused one (a malformed pointer) on stderr.
  template <typename Change>
  void edit(Change change);
  void save();
  // After the document changed: the loader's problem, and once edits pause, the numbers before running.
  void refresh();

  SceneDocument document_;
  gl::ContextInfo gl_;
  std::string checkedText_;        // the document's JSON the problem and the numbers are of
  std::optional<SceneDocument::Problem> problem_;
  std::string problemPointer_;     // the JSON pointer of problem_'s key path
  std::optional<StartNumbers> numbers_;
  std::optional<std::string> numbersError_;  // the budget's or the pre-flight's refusal
  std::string numbersText_;        // the document's JSON the numbers are of
  std::chrono::steady_clock::time_point lastEdit_;
  std::map<std::string, std::string> typing_;       // the text of fields being edited, by pointer
  std::map<std::string, std::string> newKeyNames_;  // the "add key" fields, by object pointer
  struct Field {
    ImVec2 centre;
    bool visible;  // in the panel's view, not scrolled out of it
  };
  std::map<std::string, Field> fieldCentres_;      // this frame's
  std::map<std::string, Field> lastFieldCentres_;  // the last frame's
  std::string reveal_;                             // a field to scroll into view when next drawn
  std::string saveMessage_;
  bool closeDialog_ = false;
};

}  // namespace firn
