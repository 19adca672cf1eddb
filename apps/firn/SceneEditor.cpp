#include "SceneEditor.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

#include "gl/GL.h"  // GLEW's header must come before GLFW's
#include <GLFW/glfw3.h>
#include <imgui_stdlib.h>

#include "Error.h"
#include "io/Text.h"
#include "render/Picking.h"
#include "scene/PartTransforms.h"
#include "scene/SceneObjects.h"

namespace firn {
namespace {

using Clock = std::chrono::steady_clock;

// Edits this close together are one burst: the numbers before running, which sample the bodies, wait for its end.
constexpr double kNumbersAfterEditsS = 0.3;
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

// The middle of the domain, where the panel's "add" buttons put a part.
glm::dvec3 domainCentre(const Scene& scene) {
  return scene.grid.originM + 0.5 * glm::dvec3(scene.grid.cells) * scene.grid.cellSizeM;
}

// The parts each section's "add" offers, by the names its buttons and menus give them.
const std::vector<std::pair<std::string, std::vector<std::string>>>& partKinds() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> kinds = {
      {"bodies", {"sphere", "box", "emitter"}}, {"colliders", {"plane", "sphere", "box"}},
      {"rigid_bodies", {"sphere", "box"}}};
  return kinds;
}

// A new part of `section` of kind `kind` centred at `centreM`, a few cells across (a sphere of radius 4 h, a box
// of 8 h), as a user would write it (docs/scene-format.md): snow of the first material, colliders that slip or
// part, rigid bodies of ice's density; an emitter is a box of snow poured down over its first 10 frames.
json::Json newPart(const std::string& section, const std::string& kind, const glm::dvec3& centreM, double h,
                   const std::string& material) {
  const json::Json centre = fileVector(centreM);
  const json::Json low = fileVector(centreM - 4 * h), high = fileVector(centreM + 4 * h);
  if (section == "bodies") {
    if (kind == "sphere") {
      return {{"shape", "sphere"}, {"center", centre}, {"radius", fileNumber(4 * h)}, {"material", material},
              {"particles_per_cell", 8}};
    }
    json::Json box = {{"shape", "box"}, {"min", low}, {"max", high}, {"material", material}, {"particles_per_cell", 8}};
    if (kind == "emitter") {
      box["velocity"] = json::Json::array({0, -2, 0});
      box["start_frame"] = 0;
      box["duration_frames"] = 10;
    }
    return box;
  }
  if (section == "colliders") {
    if (kind == "plane") {
      return {{"type", "plane"}, {"point", centre}, {"normal", {0, 1, 0}}, {"friction", 0.5}, {"boundary", "slip"}};
    }
    if (kind == "sphere") {
      return {{"type", "sphere"}, {"center", centre}, {"radius", fileNumber(4 * h)}, {"friction", 0.5},
              {"boundary", "separate"}};
    }
    return {{"type", "box"}, {"min", low}, {"max", high}, {"friction", 0.5}, {"boundary", "separate"}};
  }
  if (kind == "sphere") {
    return {{"shape", "sphere"}, {"center", centre}, {"radius", fileNumber(4 * h)}, {"density", 917}};
  }
  return {{"shape", "box"}, {"center", centre}, {"size", fileVector(glm::dvec3(8 * h))}, {"density", 917}};
}

// A mesh part of `section` from `path` (as the file names it) placed with its origin at `atM`.
json::Json newMeshPart(const std::string& section, const std::string& path, const glm::dvec3& atM,
                       const std::string& material) {
  if (section == "bodies") {
    return {{"shape", "mesh"}, {"path", path}, {"translate", fileVector(atM)}, {"material", material},
            {"particles_per_cell", 8}};
  }
  if (section == "colliders") {
    return {{"type", "mesh"}, {"path", path}, {"translate", fileVector(atM)}, {"friction", 0.5}, {"boundary", "separate"}};
  }
  return {{"shape", "mesh"}, {"path", path}, {"translate", fileVector(atM)}, {"density", 917}};
}

// The files a mesh may come from (assimp reads them; docs/scene-format.md).
bool isMeshFile(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".obj" || extension == ".ply" || extension == ".stl" || extension == ".gltf" ||
         extension == ".glb" || extension == ".fbx" || extension == ".off";
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
  return scene_;
}

std::optional<Scene> SceneEditor::settledScene(std::string& text) const {
  if (numbersText_ != checkedText_ || problemMessage() || handles_.dragging() || !typing_.empty() ||
      !sliding_.empty()) {
    return std::nullopt;
  }
  text = checkedText_;
  return scene_;
}

std::optional<std::string> SceneEditor::problemMessage() const {
  if (problem_) return problem_->message;
  if (startFailure_ && startFailure_->first == checkedText_) return startFailure_->second;
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
  const auto found = fieldCentres_.find(pointer);
  if (found == fieldCentres_.end() || !found->second.visible) return std::nullopt;
  return found->second.centre;
}

void SceneEditor::remember(const std::string& pointer) {
  const ImVec2 min = ImGui::GetItemRectMin(), max = ImGui::GetItemRectMax();
  const ImVec2 centre(0.5f * (min.x + max.x), 0.5f * (min.y + max.y));
  // Visible: the item's centre inside its window's clipping, where a click at it lands on the item (a list's rows
  // reach under its scroll bar; the whole row need not show).
  const ImVec2 clipMin = ImGui::GetWindowDrawList()->GetClipRectMin();
  const ImVec2 clipMax = ImGui::GetWindowDrawList()->GetClipRectMax();
  const bool visible = centre.x >= clipMin.x && centre.y >= clipMin.y && centre.x < clipMax.x && centre.y < clipMax.y &&
                       min.y >= clipMin.y && max.y <= clipMax.y;
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

bool SceneEditor::pointerBusy() {
  if (ImGui::GetCurrentContext() == nullptr) return false;  // before the window's first frame
  const ImGuiIO& io = ImGui::GetIO();
  for (int b = 0; b < 3; ++b) {
    if (io.MouseDown[b] || io.MouseReleased[b]) return true;
  }
  return false;
}

void SceneEditor::refresh() {
  const std::string text = document_.json().dump();
  if (text != checkedText_) {
    checkedText_ = text;
    scene_ = document_.sceneOrProblem(problem_);  // one reading: a mesh is loaded once per edit
    problemPointer_ = problem_ ? pointerOfKeyPath(problem_->keyPath) : "";
    allowedKeys_.clear();
    // An undo, or a part removed before it, can take the selection away.
    if (!selected_.empty() && !document_.json().contains(json::Json::json_pointer(selected_))) select("");
  }
  // The numbers sample the bodies: once edits pause, and only of a scene the loader takes. Not in a frame with a
  // button pressed, held or let go: the new lines would move the fields under a click between its press (aimed where
  // the last frame drew them) and its release.
  const bool settled = std::chrono::duration<double>(Clock::now() - lastEdit_).count() >= kNumbersAfterEditsS;
  if (problem_ || numbersText_ == checkedText_ || !settled || pointerBusy()) return;
  numbersText_ = checkedText_;
  SessionOptions options;  // `firn run`'s
  options.lastFrame = scene_->time.frames;
  try {
    numbers_ = numbersBeforeRunning(*scene_, gl_, options);
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

SceneEditor::Request SceneEditor::draw(bool running, const std::optional<ViewCamera>& view) {
  refresh();
  fieldCentres_.clear();
  Request request = Request::None;
  const ImGuiIO& io = ImGui::GetIO();
  if (headless_) drawHeadlessRunEnd();
  if (!io.WantTextInput && keyPressed(GLFW_KEY_TAB)) request = running ? Request::Edit : Request::Run;

  const bool control = io.KeyCtrl;
  if (!io.WantTextInput && control) {
    if (keyPressed(GLFW_KEY_Z) && !io.KeyShift) edit([&] { document_.undo(); });
    if (keyPressed(GLFW_KEY_Y) || (keyPressed(GLFW_KEY_Z) && io.KeyShift)) edit([&] { document_.redo(); });
    if (keyPressed(GLFW_KEY_S)) save();
    if (keyPressed(GLFW_KEY_D) && !selected_.empty() &&
        document_.json().contains(json::Json::json_pointer(selected_))) {
      const std::size_t index = std::stoul(selected_.substr(selected_.rfind('/') + 1));
      const json::Json part = document_.json()[json::Json::json_pointer(selected_)];
      edit([&] { document_.insert(parentPointer(selected_), index + 1, part); });
      select(parentPointer(selected_) + "/" + std::to_string(index + 1));
    }
  }
  // While running, the view's own keys (R resets) are the view's.
  if (!io.WantTextInput && !control && !running) {
    if (keyPressed(GLFW_KEY_W)) mode_ = HandleMode::Move;
    if (keyPressed(GLFW_KEY_E)) mode_ = HandleMode::Turn;
    if (keyPressed(GLFW_KEY_R)) mode_ = HandleMode::Scale;
    if (keyPressed(GLFW_KEY_DELETE) && !selected_.empty()) {
      const std::string removed = selected_;
      select("");
      edit([&] { document_.remove(removed); });
    }
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
  drawModes(running);
  drawProblem();
  drawHeadlessRun();
  drawNumbers();
  ImGui::Separator();
  // Edits change the document under the loop: draw from a copy.
  const json::Json top = document_.json();
  for (auto it = top.begin(); it != top.end(); ++it) {
    drawValue("/" + pointerToken(it.key()), it.key(), it.value(), 0, false);
  }
  drawAddKey("");
  if (view && scene_) followView(*view);
  drawMeshDialog();
  drawCloseDialog(request);
  ImGui::PopAllowKeyboardFocus();
  ImGui::End();
  // A field being typed into or a slider being dragged that this frame did not draw (its part folded away) will not
  // be left by the user: what it held is dropped, so that the edits can settle.
  for (std::map<std::string, std::string>::iterator it = typing_.begin(); it != typing_.end();) {
    it = fieldCentres_.count(it->first) > 0 ? std::next(it) : typing_.erase(it);
  }
  for (std::map<std::string, float>::iterator it = sliding_.begin(); it != sliding_.end();) {
    it = fieldCentres_.count(it->first) > 0 ? std::next(it) : sliding_.erase(it);
  }
  return request;
}

void SceneEditor::drawToolbar(bool running, Request& request) {
  ImGui::TextUnformatted((document_.path().filename().string() + (document_.modified() ? " *" : "")).c_str());
  ImGui::BeginDisabled(problemMessage().has_value());
  if (ImGui::Button(running ? "Edit (Tab)" : "Run (Tab)")) request = running ? Request::Edit : Request::Run;
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
  if (running) {
    ImGui::TextWrapped("Running: edits of the materials apply at the next step where the step can take them; the "
                       "others when you go back to editing (Tab).");
    if (!liveNote_.empty()) ImGui::TextWrapped("%s", liveNote_.c_str());
  }
}

void SceneEditor::drawProblem() {
  const std::optional<std::string> message = problemMessage();
  if (!message) return;
  ImGui::PushStyleColor(ImGuiCol_Text, kProblemColour);
  ImGui::TextWrapped("Cannot run: %s", message->c_str());
  ImGui::PopStyleColor();
}

void SceneEditor::noteStepCost(double msPerStep, std::size_t particles) {
  if (particles == 0 || !(msPerStep > 0)) return;
  msPerParticleStep_ = msPerStep / double(particles);
  std::printf("firn view: a step of %s particles took %.3g ms here\n", withThousands(double(particles)).c_str(),
              msPerStep);
  std::fflush(stdout);
}

void SceneEditor::drawNumbers() {
  if (!ImGui::CollapsingHeader("Before running", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (numbersText_ != checkedText_ && !problem_) ImGui::TextDisabled("(measuring the edited scene)");
  if (!numbers_) return;
  // The step's cost goes with its particles (the transfers and the deformation update are per particle); the grid's
  // passes add a little, which a rate from a run of a similar scene carries.
  // One line either way, whatever the numbers: the fields below stay where a click aims (the rate comes with a new
  // simulation, between two frames).
  if (msPerParticleStep_ > 0) {
    ImGui::Text("about %.3g ms per step here (%.3g µs per particle)", msPerParticleStep_ * double(numbers_->particles),
                msPerParticleStep_ * 1e3);
  } else {
    ImGui::TextDisabled("ms per step: timed when the scene can start");
  }
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

void SceneEditor::drawLabel(const std::string& label) {
  // The fields line up in a column, past the label and the tree's indent.
  const float startPx = ImGui::GetCursorPosX();
  ImGui::AlignTextToFramePadding();
  ImGui::TextUnformatted(label.c_str());
  ImGui::SameLine(std::max(startPx + 110.0f, 190.0f));
}

void SceneEditor::drawValue(const std::string& pointer, const std::string& label, const json::Json& value, int depth,
                            bool element) {
  ImGui::PushID(pointer.c_str());
  if (!value.is_object() && !(value.is_array() && !isFlatArray(value))) {
    drawLabel(label);
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
  // The scene's sections open at first; their parts' own objects (keyframes, a material's keys) too; and the
  // selection's, when it is picked.
  ImGui::SetNextItemOpen(depth < 3, ImGuiCond_Once);
  const auto opening = std::find(toOpen_.begin(), toOpen_.end(), pointer);
  if (opening != toOpen_.end()) {
    ImGui::SetNextItemOpen(true);
    toOpen_.erase(opening);
  }
  const bool open = ImGui::TreeNodeEx(label.c_str(), pointer == selected_ ? ImGuiTreeNodeFlags_Selected : 0);
  if (element && ImGui::IsItemClicked() && depth == 1) select(pointer);
  remember(pointer);
  if (element) {
    ImGui::SameLine();
    if (ImGui::SmallButton("duplicate")) {
      const std::size_t index = std::stoul(pointer.substr(pointer.rfind('/') + 1));
      edit([&] { document_.insert(parentPointer(pointer), index + 1, value); });
    }
    remember(pointer + "#duplicate");
    ImGui::SameLine();
    if (ImGui::SmallButton("delete")) {
      // The selection goes with the part, and with a part before it in its array (its index would name the next).
      const std::string array = parentPointer(pointer);
      if (parentPointer(selected_) == array &&
          std::stoul(selected_.substr(array.size() + 1)) >= std::stoul(pointer.substr(array.size() + 1))) {
        select("");
      }
      edit([&] { document_.remove(pointer); });
    }
    remember(pointer + "#delete");
  } else {
    ImGui::SameLine();
    if (ImGui::SmallButton("remove")) edit([&] { document_.remove(pointer); });
    remember(pointer + "#remove");
  }
  showMessageAt(pointer);
  if (open) {
    if (depth == 1 && pointer.rfind("/materials/", 0) == 0) drawMaterialSliders(pointer, label);
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

std::string SceneEditor::firstMaterial() const {
  const json::Json& document = document_.json();
  if (document.contains("materials") && document["materials"].is_object() && !document["materials"].empty()) {
    return document["materials"].begin().key();
  }
  return "snow";
}

void SceneEditor::drawArrayTools(const std::string& pointer, const json::Json& array) {
  // A part is added to a scene the loader takes: its grid places it.
  if (!scene_) return;
  for (const auto& [section, kinds] : partKinds()) {
    if (pointer != "/" + section) continue;
    for (const std::string& kind : kinds) {
      if (ImGui::SmallButton(("add " + kind).c_str())) {
        const json::Json part =
            newPart(section, kind, domainCentre(*scene_), scene_->grid.cellSizeM, firstMaterial());
        edit([&] { document_.insert(pointer, array.size(), part); });
        select(pointer + "/" + std::to_string(array.size()));
      }
      remember(pointer + "#add-" + kind);
      ImGui::SameLine();
    }
    ImGui::NewLine();
  }
}

void SceneEditor::drawAddKey(const std::string& pointer) {
  // The keys the format allows here and the file leaves out, as the loader lists them (asked once the list opens: it
  // reads the document); a new key is 0 until the user says more, and the loader names what it should hold.
  ImGui::SetNextItemWidth(200);
  const bool open = ImGui::BeginCombo("##add key", "add key…");
  remember(pointer + "#add-key");
  if (!open) return;
  auto allowed = allowedKeys_.find(pointer);
  if (allowed == allowedKeys_.end()) allowed = allowedKeys_.emplace(pointer, document_.keysAllowedAt(pointer)).first;
  const json::Json& object = pointer.empty() ? document_.json() : document_.json()[json::Json::json_pointer(pointer)];
  std::string added;
  for (const std::string& key : allowed->second) {
    if (object.contains(key)) continue;
    if (ImGui::Selectable(key.c_str())) added = key;
    remember(pointer + "#add-key/" + key);
  }
  // Where the loader lists none (a material's name, or another problem stands first), a name to type.
  std::string& name = newKeyNames_[pointer];
  ImGui::SetNextItemWidth(-60);
  ImGui::InputTextWithHint("##new key", "another key", &name);
  remember(pointer + "#new-key");
  ImGui::SameLine();
  if (ImGui::SmallButton("add") && !name.empty()) added = name;
  remember(pointer + "#add-named-key");
  ImGui::EndCombo();
  if (!added.empty()) {
    edit([&] { document_.set(pointer + "/" + pointerToken(added), 0); });
    name.clear();
  }
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

void SceneEditor::drawModes(bool running) {
  if (running) return;
  int mode = int(mode_);
  ImGui::RadioButton("Move (W)", &mode, int(HandleMode::Move));
  remember("#move");
  ImGui::SameLine();
  ImGui::RadioButton("Turn (E)", &mode, int(HandleMode::Turn));
  remember("#turn");
  ImGui::SameLine();
  ImGui::RadioButton("Scale (R)", &mode, int(HandleMode::Scale));
  remember("#scale");
  mode_ = HandleMode(mode);
  ImGui::SameLine();
  ImGui::Checkbox("Snap to cells", &snap_);
  remember("#snap");
  if (selected_.empty()) {
    ImGui::TextDisabled("Click a part in the view to select it; right-click to add one there.");
  } else {
    ImGui::TextWrapped("Selected %s: drag its handles; Delete removes it, Ctrl+D duplicates it.", selected_.c_str());
  }
}

void SceneEditor::select(const std::string& pointer) {
  if (pointer == selected_) return;
  selected_ = pointer;
  handles_.cancel();
  toOpen_.clear();
  if (pointer.empty()) return;
  // The part's tree node and its section's, opened and scrolled to.
  toOpen_ = {parentPointer(pointer), pointer};
  reveal_ = pointer;
}

void SceneEditor::addPart(const std::string& section, const json::Json& part) {
  const std::string pointer = "/" + section;
  const json::Json& document = document_.json();
  if (document.contains(section) && document[section].is_array()) {
    const std::size_t index = document[section].size();
    edit([&] { document_.insert(pointer, index, part); });
    select(pointer + "/" + std::to_string(index));
  } else {
    edit([&] { document_.set(pointer, json::Json::array({part})); });
    select(pointer + "/0");
  }
}

std::optional<HandledPart> SceneEditor::handledPart() const {
  if (selected_.empty() || !scene_) return std::nullopt;
  const std::string section = selected_.substr(1, selected_.rfind('/') - 1);
  const std::size_t index = std::stoul(selected_.substr(selected_.rfind('/') + 1));
  const json::Json::json_pointer at(selected_);
  if (!document_.json().contains(at)) return std::nullopt;
  HandledPart part;
  part.pointer = selected_;
  part.section = section;
  part.object = document_.json()[at];
  if (section == "bodies") {
    if (index >= scene_->bodies.size()) return std::nullopt;
    const Body& body = scene_->bodies[index];
    part.boundsM = std::make_pair(body.boundsMinM(), body.boundsMaxM());
    part.anchorM = 0.5 * (body.boundsMinM() + body.boundsMaxM());
    return part;
  }
  const ObjectKind kind = section == "colliders" ? ObjectKind::Collider : ObjectKind::RigidBody;
  if (kind == ObjectKind::Collider && index >= scene_->colliders.size()) return std::nullopt;
  if (kind == ObjectKind::RigidBody && index >= scene_->rigidBodies.size()) return std::nullopt;
  if (kind == ObjectKind::Collider && scene_->colliders[index].shape == ColliderShape::Plane) {
    part.anchorM = scene_->colliders[index].pointM;  // a plane has no bounds to outline
    return part;
  }
  for (const SceneObject& object : sceneObjects(*scene_)) {
    if (object.kind != kind || std::size_t(object.index) != index) continue;
    const ObjectPose pose = kind == ObjectKind::Collider ? colliderObjectPose(scene_->colliders[index], 0.0)
                                                         : initialBodyPose(scene_->rigidBodies[index]);
    const voxelizer::TriangleMesh placed = posedMesh(object.meshM, pose);
    glm::dvec3 low(std::numeric_limits<double>::infinity()), high(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& vertex : placed.vertices) {
      low = glm::min(low, vertex);
      high = glm::max(high, vertex);
    }
    part.boundsM = std::make_pair(low, high);
    // A rigid body turns about its centre of mass; a collider's handles sit in the middle of its bounds.
    part.anchorM = kind == ObjectKind::RigidBody ? pose.positionM : 0.5 * (low + high);
    return part;
  }
  return std::nullopt;
}

void SceneEditor::followView(const ViewCamera& view) {
  const ImGuiIO& io = ImGui::GetIO();
  if (const std::optional<HandledPart> part = handledPart()) {
    if (const std::optional<json::Json> moved = handles_.update(view, *part, mode_, snap_, scene_->grid.cellSizeM)) {
      edit([&] { document_.set(part->pointer, *moved); });
    }
    for (const auto& [name, centre] : handles_.targets()) fieldCentres_[name] = Field{centre, view.contains(centre)};
  }
  // A click on the view (a press and a release without a drag between, which turns the view) picks what it shows;
  // a right-click opens the menu of parts to add there.
  const bool overPanel = ImGui::IsWindowHovered(ImGuiHoveredFlags_AnyWindow);
  if (io.MouseClicked[0] || io.MouseClicked[1]) {
    pressPx_ = io.MousePos;
    pressInView_ = view.contains(io.MousePos) && !overPanel && !handles_.dragging();
  }
  const bool still = std::hypot(io.MousePos.x - pressPx_.x, io.MousePos.y - pressPx_.y) < 4;
  if (pressInView_ && still && io.MouseReleased[0]) {
    pressInView_ = false;
    const std::optional<render::PickedPart> picked = render::pickPart(*scene_, view.ray(io.MousePos));
    select(picked ? picked->pointer() : "");
  }
  if (pressInView_ && still && io.MouseReleased[1]) {
    pressInView_ = false;
    // On the surface the pointer shows, or as far off as the camera's target.
    const render::Ray ray = view.ray(io.MousePos);
    const double h = scene_->grid.cellSizeM;
    const std::optional<render::PickedPart> picked = render::pickPart(*scene_, ray);
    addAtM_ = picked ? picked->pointM + 4 * h * picked->normal
                     : ray.originM + glm::distance(glm::dvec3(view.camera.targetM), ray.originM) * ray.direction;
    if (snap_) {
      const glm::dvec3 originM = scene_->grid.originM;
      for (int i = 0; i < 3; ++i) addAtM_[i] = originM[i] + snapTo(addAtM_[i] - originM[i], h);
    }
    ImGui::OpenPopup("add here");
  }
  drawAddHere();
}

void SceneEditor::drawAddHere() {
  if (!ImGui::BeginPopup("add here")) return;
  const char* const sectionNames[] = {"snow", "collider", "rigid body"};
  for (std::size_t s = 0; s < partKinds().size(); ++s) {
    const auto& [section, kinds] = partKinds()[s];
    for (const std::string& kind : kinds) {
      const std::string name = std::string(sectionNames[s]) + " " + kind;
      if (ImGui::MenuItem(name.c_str())) {
        addPart(section, newPart(section, kind, addAtM_, scene_->grid.cellSizeM, firstMaterial()));
      }
      remember("#add-here/" + section + "/" + kind);
    }
    if (ImGui::MenuItem((std::string(sectionNames[s]) + " mesh…").c_str())) {
      meshSection_ = section;
      if (meshFolder_.empty()) meshFolder_ = std::filesystem::absolute(document_.path()).parent_path();
    }
    remember("#add-here/" + section + "/mesh");
    ImGui::Separator();
  }
  ImGui::EndPopup();
}

void SceneEditor::drawMeshDialog() {
  if (meshSection_.empty()) return;
  if (!ImGui::IsPopupOpen("Choose a mesh")) ImGui::OpenPopup("Choose a mesh");
  ImGui::SetNextWindowSize(ImVec2(420, 360), ImGuiCond_Appearing);
  if (!ImGui::BeginPopupModal("Choose a mesh")) return;
  ImGui::TextWrapped("%s", meshFolder_.string().c_str());
  // The folder's folders, then its mesh files (OBJ, PLY, STL, glTF, FBX, OFF), by name.
  std::vector<std::filesystem::path> folders, meshes;
  std::error_code error;
  for (const std::filesystem::directory_entry& entry : std::filesystem::directory_iterator(meshFolder_, error)) {
    if (entry.is_directory(error)) {
      folders.push_back(entry.path());
    } else if (isMeshFile(entry.path())) {
      meshes.push_back(entry.path());
    }
  }
  std::sort(folders.begin(), folders.end());
  std::sort(meshes.begin(), meshes.end());
  ImGui::BeginChild("files", ImVec2(0, -ImGui::GetFrameHeightWithSpacing()), true);
  if (ImGui::Selectable("../")) meshFolder_ = meshFolder_.parent_path();
  remember("#file/..");
  for (const std::filesystem::path& folder : folders) {
    if (ImGui::Selectable((folder.filename().string() + "/").c_str())) meshFolder_ = folder;
    remember("#file/" + folder.filename().string());
  }
  for (const std::filesystem::path& mesh : meshes) {
    if (ImGui::Selectable(mesh.filename().string().c_str())) {
      // Named as the scene's other paths are: from the scene file's folder.
      const std::filesystem::path sceneFolder = std::filesystem::absolute(document_.path()).parent_path();
      const std::filesystem::path relative = mesh.lexically_relative(sceneFolder);
      const std::string path = (relative.empty() ? mesh : relative).generic_string();
      addPart(meshSection_, newMeshPart(meshSection_, path, addAtM_, firstMaterial()));
      meshSection_.clear();
      ImGui::CloseCurrentPopup();
    }
    remember("#file/" + mesh.filename().string());
  }
  ImGui::EndChild();
  if (ImGui::Button("Cancel")) {
    meshSection_.clear();
    ImGui::CloseCurrentPopup();
  }
  remember("#file-cancel");
  ImGui::EndPopup();
}

void SceneEditor::drawHeadlessRunEnd() {
  headless_->poll();
  if (headless_->running() || headlessReported_) return;
  headlessReported_ = true;
  const std::string last = headless_->lines().empty() ? "" : headless_->lines().back();
  std::printf("firn view: the headless run ended (exit %d): %s\n", *headless_->exitCode(), last.c_str());
  std::fflush(stdout);
}

void SceneEditor::finishHeadlessRun() {
  if (!headless_ || !headless_->running()) return;
  headless_->wait();
  drawHeadlessRunEnd();
}

void SceneEditor::drawHeadlessRun() {
  const bool open = ImGui::CollapsingHeader("Run headless");
  remember("#headless");
  if (!open) return;
  if (headlessOut_.empty()) {
    const std::filesystem::path scene = std::filesystem::absolute(document_.path());
    headlessOut_ = (scene.parent_path() / (scene.stem().string() + "_out")).string();
  }
  const bool going = headless_ && headless_->running();
  ImGui::SetNextItemWidth(-1);
  ImGui::InputTextWithHint("##out", "output folder", &headlessOut_);
  remember("#headless-out");
  ImGui::BeginDisabled(going || problemMessage().has_value());
  if (ImGui::Button("Start the run")) {
    // `firn run` takes the scene from its file: the edits go there first.
    if (document_.modified()) save();
    if (!document_.modified()) {
      try {
        headless_ = std::make_unique<HeadlessJob>(document_.path(), headlessOut_);
        headlessReported_ = false;
        std::printf("firn view: running headless: firn run %s --out %s\n", document_.path().string().c_str(),
                    headlessOut_.c_str());
        std::fflush(stdout);
      } catch (const std::runtime_error& error) {
        saveMessage_ = std::string("run headless: ") + error.what();
      }
    }
  }
  ImGui::EndDisabled();
  remember("#run-headless");
  if (!headless_) return;
  ImGui::SameLine();
  ImGui::BeginDisabled(!going);
  if (ImGui::Button("Stop")) headless_->stop();
  ImGui::EndDisabled();
  remember("#stop-headless");
  ImGui::ProgressBar(float(headless_->fraction()));
  if (!headless_->lines().empty()) ImGui::TextWrapped("%s", headless_->lines().back().c_str());
  if (const std::optional<int> code = headless_->exitCode()) ImGui::Text("ended with exit status %d", *code);
}

void SceneEditor::drawMaterialSliders(const std::string& pointer, const std::string& name) {
  if (!scene_) return;
  const auto material = std::find_if(scene_->materials.begin(), scene_->materials.end(),
                                     [&](const Material& m) { return m.name == name; });
  if (material == scene_->materials.end()) return;
  // The model's keys (docs/scene-format.md) at the values the scene runs with, a preset's included; the moduli and
  // densities on a logarithmic scale.
  struct Slider {
    const char* key;
    const char* label;
    double value;
    float low, high;
    bool logarithmic;
  };
  const Slider youngs{"youngs_modulus", "E (Pa)", material->youngsModulusPa, 1e3f, 1e10f, true};
  const Slider poisson{"poisson_ratio", "ν", material->poissonRatio, 0.0f, 0.49f, false};
  const Slider density{"density", "ρ (kg/m³)", material->densityKgPerM3, 1.0f, 2e4f, true};
  std::vector<Slider> sliders;
  if (material->model != MaterialModel::Water) {
    sliders.push_back(youngs);
    sliders.push_back(poisson);
  }
  sliders.push_back(density);
  if (material->model == MaterialModel::Snow) {
    sliders.push_back({"critical_compression", "θc", material->criticalCompression, 0, 0.2f, false});
    sliders.push_back({"critical_stretch", "θs", material->criticalStretch, 0, 0.05f, false});
    sliders.push_back({"hardening", "ξ", material->hardening, 0, 50, false});
  } else if (material->model == MaterialModel::Water) {
    sliders.push_back({"bulk_modulus", "k (Pa)", material->bulkModulusPa, 1e3f, 1e10f, true});
    sliders.push_back({"gamma", "γ", material->gamma, 1, 10, false});
    sliders.push_back({"viscosity", "η (Pa·s)", material->viscosityPaS, 0, 10, false});
  } else if (material->model == MaterialModel::DruckerPrager &&
             !document_.json()[json::Json::json_pointer(pointer)].contains("hardening")) {
    // A constant angle; a hardening law (an array) is edited as its field.
    sliders.push_back({"friction_angle_deg", "φ (°)", material->hardeningH0Deg, 0, 89, false});
  }
  for (const Slider& slider : sliders) {
    const std::string at = pointer + "/" + slider.key;
    const std::string field = pointer + "#slider-" + slider.key;
    auto pending = sliding_.find(field);
    float value = pending != sliding_.end() ? pending->second : float(slider.value);
    drawLabel(slider.label);
    ImGui::SetNextItemWidth(-1);
    const std::string id = std::string("##") + slider.key;
    if (ImGui::SliderFloat(id.c_str(), &value, slider.low, slider.high, "%.4g",
                           slider.logarithmic ? ImGuiSliderFlags_Logarithmic : 0)) {
      sliding_[field] = value;
    }
    remember(field);
    if (ImGui::IsItemDeactivated()) {
      pending = sliding_.find(field);
      if (pending != sliding_.end()) {
        // To the four digits the slider shows.
        const double chosen = std::stod(format("%.4g", double(pending->second)));
        sliding_.erase(pending);
        edit([&] { document_.set(at, chosen); });
      }
    }
  }
}

}  // namespace firn
