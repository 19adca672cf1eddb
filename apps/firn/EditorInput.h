#pragma once
// The scene editor's input as a list of events, recorded from the window (`firn view --edit --record FILE`) and
// replayed into it (`--replay FILE`), so that editing is tested as a user edits: clicks, keys and typed text reach
// Dear ImGui as the window's own would, frame by frame. A file is a JSON array of events, each at a drawn frame
// (counted from 1):
//
//   {"frame": 5, "click": "/materials/snow/youngs_modulus"}   a left click at the centre of the field that edits a key
//                                                              (SceneEditor::fieldCentre), or of a button ("#save")
//   {"frame": 5, "mouse": [300, 120], "button": "left", "action": "press"}   a button pressed or released there
//   {"frame": 5, "mouse": [310, 120]}                          the pointer moved there
//   {"frame": 8, "drag": "#handle-x", "by": [50, 0]}           a left drag from a field's or handle's centre, `by`
//                                                              pixels over two frames, released at the third
//   {"frame": 6, "key": "A", "mods": ["ctrl"]}                 a key pressed (and released at the next frame)
//   {"frame": 7, "text": "5e5"}                                text typed
//   {"frame": 9, "close": true}                                the window's close button
//
// Keys are named as GLFW names them without its GLFW_KEY_ prefix: letters, digits, TAB, ENTER, ESCAPE, BACKSPACE,
// DELETE, SPACE, LEFT, RIGHT, UP, DOWN, HOME, END.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <imgui.h>

#include "scene/JsonChecker.h"

namespace firn {

class SceneEditor;

struct EditorEvent {
  int frame = 0;
  std::string click;                 // a field's pointer
  std::string drag;                  // a field's or handle's name, dragged from
  ImVec2 dragByPx;
  std::optional<ImVec2> mousePx;     // where the pointer is
  int button = -1;                   // 0 left, 1 right, 2 middle; with `pressed`
  bool pressed = false;
  int key = -1;                      // a GLFW key code
  bool control = false, shift = false, alt = false;
  std::string text;
  bool close = false;
};

// A file's events in order of frame; throws InputError naming the file, the event and what is wrong.
std::vector<EditorEvent> readEditorEvents(const std::filesystem::path& path);
// The events as a file reads them.
json::Json editorEventsJson(const std::vector<EditorEvent>& events);

// Plays a list of events into the ImGui frames: call apply() after the platform backend's NewFrame and before
// ImGui::NewFrame, once per drawn frame.
class EditorReplay {
 public:
  explicit EditorReplay(std::vector<EditorEvent> events) : events_(std::move(events)) {}
  // Sets this frame's pointer, buttons, keys and text in ImGui's input; returns whether an event asks to close the
  // window. A click on a field the last frame did not draw is an error (InputError): the script no longer fits. A
  // field drawn out of the panel's view is scrolled to first, and the click and the events after it wait for it.
  bool apply(int frame, SceneEditor& editor);

 private:
  std::vector<EditorEvent> events_;
  std::size_t next_ = 0;
  std::optional<ImVec2> mousePx_;
  bool buttons_[3] = {false, false, false};
  int releaseButtonAt_ = -1;  // a click's release, the frame after its press
  // A drag under way: where it started, by how much, and at which frame.
  ImVec2 dragFromPx_, dragByPx_;
  int dragStart_ = -1;
  std::vector<int> keysDown_;  // pressed in the last frame: released in this one
  // A click's field out of the panel's view is scrolled to; the frames that has taken, which a few suffice for.
  static constexpr int kRevealFrames = 4;
  int revealFrames_ = 0;
  int delayFrames_ = 0;  // the frames the events wait behind such clicks
};

// Records the window's input as events (its GLFW callbacks call these with the frame being drawn).
class EditorRecorder {
 public:
  void key(int frame, int key, int mods);
  void text(int frame, unsigned codepoint);
  void button(int frame, double xPx, double yPx, int button, bool pressed);
  void move(int frame, double xPx, double yPx);
  void close(int frame);
  // Writes the events as `--replay` reads them.
  void write(const std::filesystem::path& path) const;

 private:
  std::vector<EditorEvent> events_;
};

}  // namespace firn
