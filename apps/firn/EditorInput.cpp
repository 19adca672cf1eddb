#include "EditorInput.h"

#include <algorithm>
#include <utility>

#include "gl/GL.h"  // GLEW's header must come before GLFW's
#include <GLFW/glfw3.h>
#include <imgui_internal.h>

#include "Error.h"
#include "SceneEditor.h"
#include "io/AtomicFile.h"
#include "io/InputFile.h"

namespace firn {
namespace {

// An event file is a short script: a megabyte is tens of thousands of events.
constexpr std::uintmax_t kMaxEventFileBytes = 1 << 20;
constexpr int kMaxFrame = 100000000;

// The keys an event may name, beyond letters and digits.
const std::vector<std::pair<std::string, int>>& namedKeys() {
  static const std::vector<std::pair<std::string, int>> keys = {
      {"TAB", GLFW_KEY_TAB},       {"ENTER", GLFW_KEY_ENTER}, {"ESCAPE", GLFW_KEY_ESCAPE},
      {"BACKSPACE", GLFW_KEY_BACKSPACE}, {"DELETE", GLFW_KEY_DELETE}, {"SPACE", GLFW_KEY_SPACE},
      {"LEFT", GLFW_KEY_LEFT},     {"RIGHT", GLFW_KEY_RIGHT}, {"UP", GLFW_KEY_UP},
      {"DOWN", GLFW_KEY_DOWN},     {"HOME", GLFW_KEY_HOME},   {"END", GLFW_KEY_END}};
  return keys;
}

std::optional<int> keyCode(const std::string& name) {
  if (name.size() == 1 && name[0] >= 'A' && name[0] <= 'Z') return GLFW_KEY_A + (name[0] - 'A');
  if (name.size() == 1 && name[0] >= '0' && name[0] <= '9') return GLFW_KEY_0 + (name[0] - '0');
  for (const auto& [keyName, code] : namedKeys()) {
    if (keyName == name) return code;
  }
  return std::nullopt;
}

std::optional<std::string> keyName(int code) {
  if (code >= GLFW_KEY_A && code <= GLFW_KEY_Z) return std::string(1, char('A' + (code - GLFW_KEY_A)));
  if (code >= GLFW_KEY_0 && code <= GLFW_KEY_9) return std::string(1, char('0' + (code - GLFW_KEY_0)));
  for (const auto& [name, keyCode] : namedKeys()) {
    if (keyCode == code) return name;
  }
  return std::nullopt;
}

const json::Choices<int> kButtons = {{"left", 0}, {"right", 1}, {"middle", 2}};

EditorEvent readEvent(const json::Value& value) {
  const json::Object object(value);
  object.checkKeys({"frame", "click", "drag", "by", "mouse", "button", "action", "key", "mods", "text", "close"},
                   "an editor event");
  EditorEvent event;
  event.frame = object.required("frame").integer(1, kMaxFrame);
  int kinds = 0;
  if (const std::optional<json::Value> click = object.optional("click")) {
    event.click = click->string();
    ++kinds;
  }
  if (const std::optional<json::Value> drag = object.optional("drag")) {
    event.drag = drag->string();
    const json::Value by = object.required("by");
    const json::Json& pixels = by.json();
    if (!pixels.is_array() || pixels.size() != 2 || !pixels[0].is_number() || !pixels[1].is_number()) {
      by.fail("must be [dx, dy], how far the drag goes in pixels");
    }
    event.dragByPx = ImVec2(pixels[0].get<float>(), pixels[1].get<float>());
    ++kinds;
  } else if (object.has("by")) {
    object.fail("drag", "\"by\" goes with a drag");
  }
  if (const std::optional<json::Value> mouse = object.optional("mouse")) {
    const json::Json& place = mouse->json();
    if (!place.is_array() || place.size() != 2 || !place[0].is_number() || !place[1].is_number()) {
      mouse->fail("must be [x, y], the pointer's place in the window in pixels");
    }
    event.mousePx = ImVec2(place[0].get<float>(), place[1].get<float>());
    if (object.has("button")) {
      event.button = object.required("button").choice<int>(kButtons);
      event.pressed = object.required("action").choice<bool>({{"press", true}, {"release", false}});
    }
    ++kinds;
  } else if (object.has("button") || object.has("action")) {
    object.fail("mouse", "a button's event needs the pointer's place, [x, y]");
  }
  if (const std::optional<json::Value> key = object.optional("key")) {
    const std::optional<int> code = keyCode(key->string());
    if (!code) key->fail("is not a key an event may name (A–Z, 0–9, TAB, ENTER, ESCAPE, BACKSPACE, DELETE, SPACE, "
                         "LEFT, RIGHT, UP, DOWN, HOME, END)");
    event.key = *code;
    if (const std::optional<json::Value> mods = object.optional("mods")) {
      if (!mods->json().is_array()) mods->fail("must be a list of \"ctrl\", \"shift\" and \"alt\"");
      for (std::size_t i = 0; i < mods->json().size(); ++i) {
        const int mod = mods->element(i).choice<int>({{"ctrl", 0}, {"shift", 1}, {"alt", 2}});
        (mod == 0 ? event.control : mod == 1 ? event.shift : event.alt) = true;
      }
    }
    ++kinds;
  } else if (object.has("mods")) {
    object.fail("key", "\"mods\" go with a key");
  }
  if (const std::optional<json::Value> text = object.optional("text")) {
    event.text = text->string();
    ++kinds;
  }
  if (const std::optional<json::Value> close = object.optional("close")) {
    if (!close->json().is_boolean() || !close->json().get<bool>()) close->fail("must be true");
    event.close = true;
    ++kinds;
  }
  if (kinds != 1) value.fail("must be one of a click, a drag, a mouse event, a key, a text or a close (found " +
                             std::to_string(kinds) + ")");
  return event;
}

}  // namespace

std::vector<EditorEvent> readEditorEvents(const std::filesystem::path& path) {
  const std::string file = path.string();
  const json::Json document = json::parse(readRegularFile(path, "editor event file", kMaxEventFileBytes), file);
  const json::Value events(document, "events", file);
  if (!document.is_array()) events.fail("must be a list of events");
  std::vector<EditorEvent> read;
  for (std::size_t i = 0; i < document.size(); ++i) {
    read.push_back(readEvent(events.element(i)));
    if (i > 0 && read[i].frame < read[i - 1].frame) {
      events.element(i).fail("comes before the event listed above it (frame " + std::to_string(read[i].frame) +
                             " after " + std::to_string(read[i - 1].frame) + ")");
    }
  }
  return read;
}

json::Json editorEventsJson(const std::vector<EditorEvent>& events) {
  json::Json list = json::Json::array();
  for (const EditorEvent& event : events) {
    json::Json entry = {{"frame", event.frame}};
    if (!event.click.empty()) entry["click"] = event.click;
    if (!event.drag.empty()) {
      entry["drag"] = event.drag;
      entry["by"] = {event.dragByPx.x, event.dragByPx.y};
    }
    if (event.mousePx) {
      entry["mouse"] = {event.mousePx->x, event.mousePx->y};
      if (event.button >= 0) {
        entry["button"] = event.button == 0 ? "left" : event.button == 1 ? "right" : "middle";
        entry["action"] = event.pressed ? "press" : "release";
      }
    }
    if (event.key >= 0) {
      entry["key"] = keyName(event.key).value_or("");
      json::Json mods = json::Json::array();
      if (event.control) mods.push_back("ctrl");
      if (event.shift) mods.push_back("shift");
      if (event.alt) mods.push_back("alt");
      if (!mods.empty()) entry["mods"] = mods;
    }
    if (!event.text.empty()) entry["text"] = event.text;
    if (event.close) entry["close"] = true;
    list.push_back(entry);
  }
  return list;
}

bool EditorReplay::apply(int frame, SceneEditor& editor) {
  ImGuiIO& io = ImGui::GetIO();
  for (int key : keysDown_) io.KeysDown[key] = false;
  keysDown_.clear();
  io.KeyCtrl = io.KeyShift = io.KeyAlt = false;
  if (releaseButtonAt_ == frame) buttons_[0] = false;
  bool close = false;
  // A drag goes halfway, then all the way, then lets go; the events after it wait for its end.
  if (dragStart_ >= 0) {
    const int step = frame - dragStart_;
    const float part = std::min(float(step), 2.0f) / 2;
    mousePx_ = ImVec2(dragFromPx_.x + part * dragByPx_.x, dragFromPx_.y + part * dragByPx_.y);
    if (step >= 3) {
      buttons_[0] = false;
      dragStart_ = -1;
    } else {
      ++delayFrames_;
    }
  }
  for (; dragStart_ < 0 && next_ < events_.size() && events_[next_].frame + delayFrames_ <= frame; ++next_) {
    const EditorEvent& event = events_[next_];
    const std::string& target = !event.click.empty() ? event.click : event.drag;
    if (!target.empty()) {
      const std::optional<ImVec2> centre = editor.fieldCentre(target);
      // A field scrolled out of the panel is scrolled into it first: the click or drag, and the events after it, wait.
      if (!centre && editor.drewField(target) && revealFrames_ < kRevealFrames) {
        editor.reveal(target);
        ++revealFrames_;
        ++delayFrames_;
        break;
      }
      if (!centre) {
        throw InputError("--replay: the event at frame " + std::to_string(event.frame) +
                         (event.click.empty() ? " drags \"" : " clicks \"") + target +
                         "\", which the editor did not draw in the frame before, or not where a click can reach it");
      }
      revealFrames_ = 0;
      mousePx_ = centre;
      buttons_[0] = true;
      if (!event.drag.empty()) {
        dragFromPx_ = *centre;
        dragByPx_ = event.dragByPx;
        dragStart_ = frame;
        ++next_;
        break;
      }
      releaseButtonAt_ = frame + 1;
    }
    if (event.mousePx) mousePx_ = event.mousePx;
    if (event.button >= 0) buttons_[event.button] = event.pressed;
    if (event.key >= 0) {
      io.KeysDown[event.key] = true;
      keysDown_.push_back(event.key);
      io.KeyCtrl = event.control;
      io.KeyShift = event.shift;
      io.KeyAlt = event.alt;
    }
    if (!event.text.empty()) io.AddInputCharactersUTF8(event.text.c_str());
    close = close || event.close;
  }
  // The scripted pointer stands in for the window's own (which the platform backend has just read).
  if (mousePx_) io.MousePos = *mousePx_;
  for (int b = 0; b < 3; ++b) io.MouseDown[b] = buttons_[b];
  return close;
}

void EditorRecorder::key(int frame, int key, int mods) {
  if (!keyName(key)) return;  // modifiers alone, and keys an event cannot name
  EditorEvent event;
  event.frame = frame;
  event.key = key;
  event.control = (mods & GLFW_MOD_CONTROL) != 0;
  event.shift = (mods & GLFW_MOD_SHIFT) != 0;
  event.alt = (mods & GLFW_MOD_ALT) != 0;
  events_.push_back(event);
}

void EditorRecorder::text(int frame, unsigned codepoint) {
  // As UTF-8 (ImGui's own encoder), joined with the text typed just before in the same frame.
  char bytes[5];
  const std::string utf8 = ImTextCharToUtf8(bytes, codepoint);
  if (!events_.empty() && events_.back().frame == frame && !events_.back().text.empty()) {
    events_.back().text += utf8;
    return;
  }
  EditorEvent event;
  event.frame = frame;
  event.text = utf8;
  events_.push_back(event);
}

void EditorRecorder::button(int frame, double xPx, double yPx, int button, bool pressed) {
  if (button < 0 || button > 2) return;
  EditorEvent event;
  event.frame = frame;
  event.mousePx = ImVec2(float(xPx), float(yPx));
  event.button = button;
  event.pressed = pressed;
  events_.push_back(event);
}

void EditorRecorder::move(int frame, double xPx, double yPx) {
  // One place a frame is enough: the pointer is read once a frame.
  if (!events_.empty() && events_.back().frame == frame && events_.back().mousePx && events_.back().button < 0) {
    events_.back().mousePx = ImVec2(float(xPx), float(yPx));
    return;
  }
  EditorEvent event;
  event.frame = frame;
  event.mousePx = ImVec2(float(xPx), float(yPx));
  events_.push_back(event);
}

void EditorRecorder::close(int frame) {
  EditorEvent event;
  event.frame = frame;
  event.close = true;
  events_.push_back(event);
}

void EditorRecorder::write(const std::filesystem::path& path) const {
  writeFileAtomically(path, editorEventsJson(events_).dump(1) + "\n", "editor event file");
}

}  // namespace firn
