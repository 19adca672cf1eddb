#include "SceneEditor.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "gl/GL.h"  // GLEW's header must come before GLFW's
#include <GLFW/glfw3.h>
#include <imgui_stdlib.h>

#include "Error.h"
#include "io/Text.h"

namespace firn {
namespace {

using Clock = std::chrono::steady_clock;

// Edits this close together are one burst: the numbers before running, which sample the bodies, wait for its end.
constexpr double kNumbersAfterEditsS = 0.3;
constexpr float kPanelWidthPx = 460;
const ImVec4 kProblemColour(1.0f, 0.45f, 0.4f, 1.0f);
const ImVec4 kWarningColour(1.0f, 0.8f, 0.3f, 1.0f);

// A key as a token of a JSON pointer (RFC 6901: "~" and "/" escaped).
std::string pointerToken(const std::string& key) {
  std::string token;
  for (char c : key) {
    if (c == '~') {
      token += "~0";
    } else if (c == '/') {
      token += "~1";
    } else {
      token += c;
    }
  }
  return token;
}

// The JSON pointer of a loader's key path: "bodies[1].radius" → "/bodies/1/radius".
std::string pointerOfKeyPath(const std::string& keyPath) {
  if (keyPath.empty()) return "";
  std::string pointer = "/";
  for (char c : keyPath) {
    if (c == '.' || c == '[') {
      pointer += '/';
    } else if (c != ']') {
      pointer += c;
    }
  }
  return pointer;
}

std::string parentPointer(const std::string& pointer) { return pointer.substr(0, pointer.rfind('/')); }

// A value edited as text: a string as itself; anything else as its JSON ("0.12", "[0.4, 0.45, 0.48]").
std::string leafText(const json::Json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

// The value a field's text makes: a string stays a string; other text is read as JSON, and text that is no JSON
// becomes a string, so that the loader says what the key should hold ("must be a number (got "abc")").
json::Json valueOfText(const std::string& text, const json::Json& before) {
  if (before.is_string()) return json::Json(text);
  json::Json parsed = json::Json::parse(text, nullptr, false);
  return parsed.is_discarded() ? json::Json(text) : parsed;
}

// Whether an array is edited as one field: numbers or strings only (a vector, a list of names).
bool isFlatArray(const json::Json& value) {
  if (!value.is_array()) return false;
  for (const json::Json& element : value) {
    if (!element.is_number() && !element.is_string() && !element.is_boolean()) return false;
  }
  return true;
}

// An element's heading: its index and what it is ("[0] sphere", "[1] mesh ../meshes/boulder.obj").
std::string elementLabel(std::size_t index, const json::Json& element) {
  std::string label = "[" + std::to_string(index) + "]";
  if (!element.is_object()) return label;
  for (const char* key : {"shape", "type", "path"}) {
    if (element.contains(key) && element[key].is_string()) label += " " + element[key].get<std::string>();
  }
  return label;
}

// The middle of the domain, where a new part is put.
json::Json domainCentre(const Scene& scene) {
  const glm::dvec3 centre = scene.grid.originM + 0.5 * glm::dvec3(scene.grid.cells) * scene.grid.cellSizeM;
  return json::Json::array({centre.x, centre.y, centre.z});
}

// The parts a section's "add" buttons make: a sphere and a box of a few cells at the domain's centre, as a user would
// write them (docs/scene-format.md).
std::vector<std::pair<std::string, json::Json>> newParts(const std::string& section, const Scene& scene,
                                                         const json::Json& document) {
  const double h = scene.grid.cellSizeM;
  const json::Json centre = domainCentre(scene);
  const json::Json size = json::Json::array({8 * h, 8 * h, 8 * h});
  std::string material = "snow";
  if (document.contains("materials") && document["materials"].is_object() && !document["materials"].empty()) {
    material = document["materials"].begin().key();
  }
  if (section == "/bodies") {
    return {{"sphere", {{"shape", "sphere"}, {"center", centre}, {"radius", 4 * h}, {"material", material},
                        {"particles_per_cell", 8}}},
            {"box", {{"shape", "box"}, {"center", centre}, {"size", size}, {"material", material},
                     {"particles_per_cell", 8}}}};
  }
  if (section == "/colliders") {
    return {{"plane", {{"type", "plane"}, {"point", centre}, {"normal", {0, 1, 0}}, {"friction", 0.5},
                       {"boundary", "slip"}}},
            {"sphere", {{"type", "sphere"}, {"center", centre}, {"radius", 4 * h}, {"friction", 0.5},
                        {"boundary", "separate"}}},
            {"box", {{"type", "box"}, {"center", centre}, {"size", size}, {"friction", 0.5}, {"boundary", "separate"}}}};
  }
  if (section == "/rigid_bodies") {
    return {{"sphere", {{"shape", "sphere"}, {"center", centre}, {"radius", 4 * h}, {"density", 917}}},
            {"box", {{"shape", "box"}, {"center", centre}, {"size", size}, {"density", 917}}}};
  }
  return {};
}

bool keyPressed(int key) { return ImGui::IsKeyPressed(key, false); }

}  // namespace

SceneEditor::SceneEditor(SceneDocument document, const gl::ContextInfo& gl)
    : document_(std::move(document)), gl_(gl) {
  refresh();
}

int SceneEditor::panelWidthPx(GLFWwindow* window) {
  int windowPx = 0, framebufferPx = 0, heightPx = 0;
  glfwGetWindowSize(window, &windowPx, &heightPx);
  glfwGetFramebufferSize(window, &framebufferPx, &heightPx);
  return windowPx > 0 ? int(kPanelWidthPx * float(framebufferPx) / float(windowPx)) : 0;
}

std::optional<Scene> SceneEditor::runnableScene() const {
  if (problemMessage()) return std::nullopt;
  return document_.scene();
}

std::optional<std::string> SceneEditor::problemMessage() const {
  if (problem_) return problem_->message;
  if (numbersError_ && numbersText_ == checkedText_) return numbersError_;
  return std::nullopt;
}

bool SceneEditor::closeRequested() {
  if (!document_.modified()) return true;
  closeDialog_ = true;
  std::printf("firn view: %s has changes not saved: the window asks whether to save them\n",
              document_.path().string().c_str());
  std::fflush(stdout);
  return false;
}

std::optional<ImVec2> SceneEditor::fieldCentre(const std::string& pointer) const {
  const auto found = lastFieldCentres_.find(pointer);
  if (found == lastFieldCentres_.end() || !found->second.visible) return std::nullopt;
  return found->second.centre;
}

void SceneEditor::remember(const std::string& pointer) {
  const ImVec2 min = ImGui::GetItemRectMin(), max = ImGui::GetItemRectMax();
  const ImVec2 centre(0.5f * (min.x + max.x), 0.5f * (min.y + max.y));
  // Visible: the whole item inside the panel's clipping, so that a click at its centre lands on it.
  const ImVec2 clipMin = ImGui::GetWindowDrawList()->GetClipRectMin();
  const ImVec2 clipMax = ImGui::GetWindowDrawList()->GetClipRectMax();
  const bool visible = min.x >= clipMin.x && min.y >= clipMin.y && max.x <= clipMax.x && max.y <= clipMax.y;
  fieldCentres_[pointer] = Field{centre, visible};
  if (pointer == reveal_) {
    ImGui::SetScrollHereY(0.5f);
    reveal_.clear();
  }
}

template <typename Change>
void SceneEditor::edit(Change change) {
  try {
    change();
    lastEdit_ = Clock::now();
    saveMessage_.clear();
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "firn view: edit refused: %s\n", error.what());
  }
  refresh();
}

void SceneEditor::refresh() {
  const std::string text = document_.json().dump();
  if (text != checkedText_) {
    checkedText_ = text;
    problem_ = document_.problem();
    problemPointer_ = problem_ ? pointerOfKeyPath(problem_->keyPath) : "";
  }
  // The numbers sample the bodies: once edits pause, and only of a scene the loader takes.
  const bool settled = std::chrono::duration<double>(Clock::now() - lastEdit_).count() >= kNumbersAfterEditsS;
  if (problem_ || numbersText_ == checkedText_ || !settled) return;
  numbersText_ = checkedText_;
  SessionOptions options;  // `firn run`'s
  options.lastFrame = document_.scene().time.frames;
  try {
    numbers_ = numbersBeforeRunning(document_.scene(), gl_, options);
    numbersError_.reset();
    std::printf("firn view: before running:\n");
    for (const std::string& line : numbers_->lines) std::printf("firn view: %s\n", line.c_str());
    std::fflush(stdout);
  } catch (const InputError& error) {
    numbers_.reset();
    numbersError_ = error.what();
    std::printf("firn view: cannot run: %s\n", error.what());
    std::fflush(stdout);
  }
}

SceneEditor::Request SceneEditor::draw(bool running) {
  refresh();
  lastFieldCentres_ = std::move(fieldCentres_);
  fieldCentres_.clear();
  Request request = Request::None;
  const ImGuiIO& io = ImGui::GetIO();
  if (!io.WantTextInput && keyPressed(GLFW_KEY_TAB)) request = running ? Request::Edit : Request::Run;
  if (running) return request;

  const bool control = io.KeyCtrl;
  if (!io.WantTextInput && control) {
    if (keyPressed(GLFW_KEY_Z) && !io.KeyShift) edit([&] { document_.undo(); });
    if (keyPressed(GLFW_KEY_Y) || (keyPressed(GLFW_KEY_Z) && io.KeyShift)) edit([&] { document_.redo(); });
    if (keyPressed(GLFW_KEY_S)) save();
  }

  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(kPanelWidthPx, io.DisplaySize.y));
  // The scroll bar always there, so that the wrapped lines keep their width and the fields their places as the
  // panel's content grows past its height.
  ImGui::Begin("Scene", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                     ImGuiWindowFlags_AlwaysVerticalScrollbar);
  // Tab runs the scene: it does not step from field to field.
  ImGui::PushAllowKeyboardFocus(false);
  drawToolbar(running, request);
  drawProblem();
  drawNumbers();
  ImGui::Separator();
  for (auto it = document_.json().begin(); it != document_.json().end(); ++it) {
    drawValue("/" + pointerToken(it.key()), it.key(), it.value(), 0, false);
  }
  drawAddKey("");
  drawCloseDialog(request);
  ImGui::PopAllowKeyboardFocus();
  ImGui::End();
  return request;
}

void SceneEditor::drawToolbar(bool running, Request& request) {
  ImGui::TextUnformatted((document_.path().filename().string() + (document_.modified() ? " *" : "")).c_str());
  ImGui::BeginDisabled(problemMessage().has_value());
  if (ImGui::Button("Run (Tab)")) request = running ? Request::Edit : Request::Run;
  ImGui::EndDisabled();
  remember("#run");
  ImGui::SameLine();
  if (ImGui::Button("Save (Ctrl+S)")) save();
  remember("#save");
  ImGui::SameLine();
  // Each button's state as it was drawn: its press changes the document.
  ImGui::BeginDisabled(!document_.canUndo());
  if (ImGui::Button("Undo")) edit([&] { document_.undo(); });
  ImGui::EndDisabled();
  remember("#undo");
  ImGui::SameLine();
  ImGui::BeginDisabled(!document_.canRedo());
  if (ImGui::Button("Redo")) edit([&] { document_.redo(); });
  ImGui::EndDisabled();
  remember("#redo");
  if (!saveMessage_.empty()) ImGui::TextWrapped("%s", saveMessage_.c_str());
}

void SceneEditor::drawProblem() {
  const std::optional<std::string> message = problemMessage();
  if (!message) return;
  ImGui::PushStyleColor(ImGuiCol_Text, kProblemColour);
  ImGui::TextWrapped("Cannot run: %s", message->c_str());
  ImGui::PopStyleColor();
}

void SceneEditor::drawNumbers() {
  if (!ImGui::CollapsingHeader("Before running", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (numbersText_ != checkedText_ && !problem_) ImGui::TextDisabled("(measuring the edited scene)");
  if (!numbers_) return;
  ImGui::TextWrapped("particles: %s of at most %s (%s)", withThousands(double(numbers_->particles)).c_str(),
              withThousands(double(numbers_->maxParticles)).c_str(), numbers_->limit.c_str());
  for (const std::string& line : numbers_->lines) {
    const bool warning = line.rfind("warning: ", 0) == 0;
    if (warning) ImGui::PushStyleColor(ImGuiCol_Text, kWarningColour);
    ImGui::TextWrapped("%s", line.c_str());
    if (warning) ImGui::PopStyleColor();
  }
}

void SceneEditor::showMessageAt(const std::string& pointer) {
  if (!problem_ || problemPointer_ != pointer) return;
  ImGui::PushStyleColor(ImGuiCol_Text, kProblemColour);
  ImGui::TextWrapped("%s", problem_->message.c_str());
  ImGui::PopStyleColor();
}

void SceneEditor::drawValue(const std::string& pointer, const std::string& label, const json::Json& value, int depth,
                            bool element) {
  ImGui::PushID(pointer.c_str());
  if (!value.is_object() && !(value.is_array() && !isFlatArray(value))) {
    const float startPx = ImGui::GetCursorPosX();
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted(label.c_str());
    ImGui::SameLine(std::max(startPx + 110.0f, 190.0f));
    drawLeaf(pointer, value);
    // Right-click on the field: the key out of the file (the loader says if it may not be).
    if (ImGui::BeginPopupContextItem("key menu")) {
      if (ImGui::MenuItem(element ? "delete" : "remove key")) edit([&] { document_.remove(pointer); });
      ImGui::EndPopup();
    }
    showMessageAt(pointer);
    ImGui::PopID();
    return;
  }
  // The scene's sections open at first; their parts' own objects (keyframes, a material's keys) too.
  ImGui::SetNextItemOpen(depth < 3, ImGuiCond_Once);
  const bool open = ImGui::TreeNode(label.c_str());
  remember(pointer);
  if (element) {
    ImGui::SameLine();
    if (ImGui::SmallButton("duplicate")) {
      const std::size_t index = std::stoul(pointer.substr(pointer.rfind('/') + 1));
      edit([&] { document_.insert(parentPointer(pointer), index + 1, value); });
    }
    remember(pointer + "#duplicate");
    ImGui::SameLine();
    if (ImGui::SmallButton("delete")) edit([&] { document_.remove(pointer); });
    remember(pointer + "#delete");
  } else {
    ImGui::SameLine();
    if (ImGui::SmallButton("remove")) edit([&] { document_.remove(pointer); });
    remember(pointer + "#remove");
  }
  showMessageAt(pointer);
  if (open) {
    // Edits change the document under the loop: draw from a copy.
    const json::Json children = value;
    if (children.is_object()) {
      for (auto it = children.begin(); it != children.end(); ++it) {
        drawValue(pointer + "/" + pointerToken(it.key()), it.key(), it.value(), depth + 1, false);
      }
      // A key the loader names that is not there (a required one left out).
      if (problem_ && parentPointer(problemPointer_) == pointer && !document_.json().contains(
                                                                      json::Json::json_pointer(problemPointer_))) {
        ImGui::PushStyleColor(ImGuiCol_Text, kProblemColour);
        ImGui::TextWrapped("%s", problem_->message.c_str());
        ImGui::PopStyleColor();
      }
      drawAddKey(pointer);
    } else {
      for (std::size_t i = 0; i < children.size(); ++i) {
        drawValue(pointer + "/" + std::to_string(i), elementLabel(i, children[i]), children[i], depth + 1, true);
      }
      drawArrayTools(pointer, children);
    }
    ImGui::TreePop();
  }
  ImGui::PopID();
}

void SceneEditor::drawLeaf(const std::string& pointer, const json::Json& value) {
  ImGui::SetNextItemWidth(-1);
  if (value.is_boolean()) {
    bool checked = value.get<bool>();
    if (ImGui::Checkbox("##value", &checked)) edit([&] { document_.set(pointer, checked); });
    remember(pointer);
    return;
  }
  // A material's preset: the presets by name.
  const std::string key = pointer.substr(pointer.rfind('/') + 1);
  if (key == "preset" && pointer.rfind("/materials/", 0) == 0 && value.is_string()) {
    if (ImGui::BeginCombo("##value", value.get<std::string>().c_str())) {
      for (const Material& preset : snowPresets()) {
        if (ImGui::Selectable(preset.name.c_str(), preset.name == value.get<std::string>())) {
          edit([&] { document_.set(pointer, preset.name); });
        }
      }
      ImGui::EndCombo();
    }
    remember(pointer);
    return;
  }
  // The text stays the field's own while it is edited; the edit is made when the field is left (or Enter).
  auto typing = typing_.find(pointer);
  std::string text = typing != typing_.end() ? typing->second : leafText(value);
  if (ImGui::InputText("##value", &text)) typing_[pointer] = text;
  remember(pointer);
  if (ImGui::IsItemDeactivated()) {
    typing = typing_.find(pointer);
    if (typing != typing_.end()) {
      const json::Json changed = valueOfText(typing->second, value);
      typing_.erase(typing);
      if (changed != value) edit([&] { document_.set(pointer, changed); });
    }
  }
}

void SceneEditor::drawArrayTools(const std::string& pointer, const json::Json& array) {
  std::optional<Scene> scene;
  try {
    scene = document_.scene();
  } catch (const InputError&) {
    // A part is added to a scene the loader takes: its grid places it.
  }
  if (scene) {
    for (const auto& [name, part] : newParts(pointer, *scene, document_.json())) {
      if (ImGui::SmallButton(("add " + name).c_str())) edit([&] { document_.insert(pointer, array.size(), part); });
      remember(pointer + "#add-" + name);
      ImGui::SameLine();
    }
    ImGui::NewLine();
  }
}

void SceneEditor::drawAddKey(const std::string& pointer) {
  std::string& name = newKeyNames_[pointer];
  ImGui::SetNextItemWidth(160);
  ImGui::InputTextWithHint("##new key", "new key", &name);
  remember(pointer + "#new-key");
  ImGui::SameLine();
  if (ImGui::SmallButton("add key") && !name.empty()) {
    // 0 until the user says more: the loader names what the key should hold.
    edit([&] { document_.set(pointer + "/" + pointerToken(name), 0); });
    name.clear();
  }
  remember(pointer + "#add-key");
}

void SceneEditor::save() {
  try {
    document_.save(document_.path());
    saveMessage_ = "saved " + document_.path().string();
    std::printf("firn view: saved %s\n", document_.path().string().c_str());
    std::fflush(stdout);
  } catch (const Error& error) {
    saveMessage_ = std::string("not saved: ") + error.what();
    std::printf("firn view: not saved: %s\n", error.what());
    std::fflush(stdout);
  }
}

void SceneEditor::drawCloseDialog(Request& request) {
  if (closeDialog_) {
    ImGui::OpenPopup("Unsaved changes");
    closeDialog_ = false;
  }
  if (!ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  ImGui::Text("%s has changes that are not saved.", document_.path().filename().string().c_str());
  if (ImGui::Button("Save and quit")) {
    save();
    if (!document_.modified()) request = Request::Quit;
    ImGui::CloseCurrentPopup();
  }
  remember("#save-and-quit");
  ImGui::SameLine();
  if (ImGui::Button("Quit without saving")) {
    request = Request::Quit;
    ImGui::CloseCurrentPopup();
  }
  remember("#quit-without-saving");
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
  remember("#cancel");
  ImGui::EndPopup();
}

}  // namespace firn
