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
#include <memory>
#include <utility>
#include <optional>
#include <string>
#include <vector>

#include <imgui.h>

struct GLFWwindow;

#include "HeadlessJob.h"
#include "PartHandles.h"
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
  // editing it; the keys are left to the view while it runs, but for Tab (back to editing). While editing, `view` is
  // where the window shows the scene: a click there picks the part it shows (its handles then move, turn or scale
  // it), and a right-click adds a part where it points.
  Request draw(bool running, const std::optional<ViewCamera>& view);

  // The panel's width in the window's pixels, and in its framebuffer's: the view beside it starts there.
  static constexpr float kPanelWidthPx = 460;
  static int panelWidthPx(GLFWwindow* window);

  const SceneDocument& document() const { return document_; }
  // The scene to run: the document's, when the loader and the numbers before running found no problem.
  std::optional<Scene> runnableScene() const;
  // The document's JSON (`text`) and its scene once edits have settled (the numbers before running are of it, no drag
  // or typing is under way) and it can run: the window shows it while editing. Nothing before then.
  std::optional<Scene> settledScene(std::string& text) const;
  // The loader's or the pre-flight's message while the scene cannot run.
  std::optional<std::string> problemMessage() const;
  // The window asks to close: at once without unsaved changes (true), else after the user's answer in a dialog.
  bool closeRequested();

  // The centre of the field that edits `pointer` ("/materials/snow/youngs_modulus"), or of the part's heading, in
  // the last frame drawn, in the window's coordinates; nothing if it was not drawn. Scripted input clicks there.
  std::optional<ImVec2> fieldCentre(const std::string& pointer) const;
  // Whether the last frame drew that field at all, in view or scrolled out of it; reveal() scrolls it into view.
  bool drewField(const std::string& pointer) const { return fieldCentres_.count(pointer) > 0; }
  void reveal(const std::string& pointer) { reveal_ = pointer; }

  // What a step of the scene in the window cost here: `msPerStep` for `particles` particles (timed at its start, or
  // while it ran). The numbers before running estimate the edited scene's step at this rate per particle.
  void noteStepCost(double msPerStep, std::size_t particles);

  // The window could not start the scene of the document's JSON `text` (InputError's `message`: a setting of the
  // window's own, such as the surface's, that the numbers before running do not check): it stays the panel's
  // problem, and cannot run, until the document changes.
  void noteStartFailure(const std::string& text, const std::string& message) { startFailure_ = {text, message}; }

  // What became of the last edit made while running (applied live, or waiting for the next start), for the panel.
  void noteLive(const std::string& note) { liveNote_ = note; }

  // A headless run the panel started, still going: waited for (a scripted window's end), or stopped.
  void finishHeadlessRun();

  // Whether a press at `px` falls on the selected part's handles (the view does not turn then), or a drag of them
  // lasts.
  bool holdsPointer(const ImVec2& px) const { return handles_.dragging() || handles_.handleAt(px); }
  // The selected part's pointer ("/bodies/0"), or empty.
  const std::string& selected() const { return selected_; }

 private:
  void drawToolbar(bool running, Request& request);
  void drawNumbers();
  void drawProblem();
  // `element`: the value is an element of an array (duplicated and deleted), else an object's key (removed).
  void drawValue(const std::string& pointer, const std::string& label, const json::Json& value, int depth,
                 bool element);
  void drawLeaf(const std::string& pointer, const json::Json& value);
  // A field's label, and the cursor at the column where the fields start.
  void drawLabel(const std::string& label);
  void drawArrayTools(const std::string& pointer, const json::Json& array);
  void drawAddKey(const std::string& pointer);
  void drawCloseDialog(Request& request);
  void drawModes(bool running);
  // Sliders for the material's keys, at the values it runs with; a release is one edit of the key.
  void drawMaterialSliders(const std::string& pointer, const std::string& name);
  void drawHeadlessRun();
  // Reads the headless run's output, and reports its end once.
  void drawHeadlessRunEnd();
  // The name of the scene's first material, which new snow is made of ("snow" where it has none).
  std::string firstMaterial() const;
  // The view's picking, handles and "add here" menu.
  void followView(const ViewCamera& view);
  void drawAddHere();
  void drawMeshDialog();
  void select(const std::string& pointer);
  // Adds `part` to the end of its section ("/bodies"), the section made where the file has none, and selects it.
  void addPart(const std::string& section, const json::Json& part);
  // The selected part as its handles need it, from the loaded scene; nothing if there is none or it is not loaded.
  std::optional<HandledPart> handledPart() const;
  void showMessageAt(const std::string& pointer);
  void remember(const std::string& pointer);
  // Applies an edit through `change`, reporting a refused one (a malformed pointer) on stderr.
  template <typename Change>
  void edit(Change change);
  void save();
  // After the document changed: the loader's problem, and once edits pause, the numbers before running.
  void refresh();
  // Whether a mouse button is down, or let go, in this frame.
  static bool pointerBusy();

  SceneDocument document_;
  gl::ContextInfo gl_;
  std::string checkedText_;        // the document's JSON the problem and the numbers are of
  std::optional<Scene> scene_;     // the document as the loader reads it, while it has no problem
  std::optional<SceneDocument::Problem> problem_;
  std::string problemPointer_;     // the JSON pointer of problem_'s key path
  std::optional<StartNumbers> numbers_;
  std::optional<std::string> numbersError_;  // the budget's or the pre-flight's refusal
  double msPerParticleStep_ = 0;   // measured while running in this window; 0 before
  std::string liveNote_;
  std::optional<std::pair<std::string, std::string>> startFailure_;  // the JSON that failed to start, and why
  std::string numbersText_;        // the document's JSON the numbers are of
  std::chrono::steady_clock::time_point lastEdit_;
  std::map<std::string, std::string> typing_;       // the text of fields being edited, by pointer
  std::map<std::string, float> sliding_;            // the value of sliders being dragged, by field name
  std::map<std::string, std::string> newKeyNames_;  // the "add key" fields, by object pointer
  std::map<std::string, std::vector<std::string>> allowedKeys_;  // the format's keys, by object pointer
  struct Field {
    ImVec2 centre;
    bool visible;  // in the panel's view, not scrolled out of it
  };
  std::map<std::string, Field> fieldCentres_;      // the frame's: complete between two frames
  std::string reveal_;                             // a field to scroll into view when next drawn
  std::string saveMessage_;
  bool closeDialog_ = false;
  // Selecting and handling parts in the view.
  std::string selected_;
  std::vector<std::string> toOpen_;  // tree nodes to open for the selection (it and its parents)
  PartHandles handles_;
  HandleMode mode_ = HandleMode::Move;
  bool snap_ = false;
  ImVec2 pressPx_;
  bool pressInView_ = false;  // the last press fell on the view, not the panel or a handle
  glm::dvec3 addAtM_{0.0};     // where the "add here" menu puts a part
  // `firn run` of the saved scene, started from the panel, and where it writes.
  std::unique_ptr<HeadlessJob> headless_;
  std::string headlessOut_;
  bool headlessReported_ = false;
  std::string meshSection_;   // the mesh dialog's: the section a chosen mesh joins ("" while closed)
  std::filesystem::path meshFolder_;
};

}  // namespace firn
