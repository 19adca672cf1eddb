// The scene editor (`firn view SCENE --edit`, apps/firn/SceneEditor.h) as a user drives it: scripted clicks, keys and
// text replayed into the window under a virtual X server (apps/firn/EditorInput.h), the file it saves, the loader's
// message that blocks a bad value from running, the question before quitting with changes unsaved, and the numbers
// it shows before running, which are `firn run`'s.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "Cli.h"
#include "GlTest.h"
#include "io/InputFile.h"
#include "render/Camera.h"
#include "run/SimulationSession.h"
#include "scene/Scene.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::kBallScene;
using firn::test::kOnXvfb;
using firn::test::linesAfter;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;
using Json = nlohmann::ordered_json;

Json readJson(const fs::path& path) {
  std::ifstream in(path);
  return Json::parse(in);
}

Result edit(const fs::path& scene, const fs::path& events, int frames, const std::string& more = "") {
  return runFirn("view " + scene.string() + " --edit --replay " + events.string() + " --frames " +
                     std::to_string(frames) + " --width 1000 --height 720" + more,
                 kOnXvfb);
}

// The steps of the run the window ended in: "firn view: 40 frames, 30 steps, …".
int stepsTaken(const std::string& output) {
  std::smatch match;
  static const std::regex ending(R"(firn view: [0-9]+ frames, ([0-9]+) steps)");
  return std::regex_search(output, match, ending) ? std::stoi(match[1]) : -1;
}

// A user adds Young's modulus to the material and leaves it at 0: the loader's message stands, and Tab does not run
// the scene. Then the user types 5e5 into the field, saves with Ctrl+S and runs with Tab: the file holds what the
// user typed and nothing else changed (every other key and the keys' order kept), and the window steps the scene.
TEST(SceneEditor, EditsAKeyShowsTheLoadersMessageSavesAndRuns) {
  const fs::path folder = freshDirectory("scene_editor_edit");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const fs::path events = writeScene(folder, "events.json", R"([
    {"frame": 3, "click": "/materials/snow#add-key"},
    {"frame": 6, "click": "/materials/snow#add-key/youngs_modulus"},
    {"frame": 9, "key": "TAB"},
    {"frame": 11, "click": "/materials/snow/youngs_modulus"},
    {"frame": 13, "key": "A", "mods": ["ctrl"]},
    {"frame": 14, "text": "5e5"},
    {"frame": 15, "key": "ENTER"},
    {"frame": 18, "key": "S", "mods": ["ctrl"]},
    {"frame": 20, "key": "TAB"}])");
  const Result result = edit(scene, events, 40);
  ASSERT_EQ(result.exitCode, 0) << result.output;

  Json expected = Json::parse(kBallScene);
  expected["materials"]["snow"]["youngs_modulus"] = 5e5;
  EXPECT_EQ(readJson(scene), expected) << result.output;
  // The bad value's message, the loader's own, and the run it refused before the save.
  const std::string message = scene.string() + ": materials.snow.youngs_modulus: must be greater than 0 (got 0)";
  const std::vector<std::string> refused = linesAfter(result.output, "firn view: cannot run: ");
  ASSERT_FALSE(refused.empty()) << result.output;
  EXPECT_EQ(refused.front(), message);
  EXPECT_LT(result.output.find(message), result.output.find("firn view: saved " + scene.string())) << result.output;
  // Run from frame 20 of 40: the window stepped (1 ms steps of a 20 ms frame, as many as its budget per frame allows).
  EXPECT_GT(stepsTaken(result.output), 0) << result.output;
}

// Closing the window with an edit unsaved asks first. "Cancel" keeps the window; "Save and quit" saves the scene as
// the edits left it (a body duplicated, the duplicate undone and redone: two bodies) and closes the window before its
// scripted frames end; "Quit without saving" leaves the file as it was.
TEST(SceneEditor, AsksBeforeQuittingWithChangesUnsaved) {
  const fs::path folder = freshDirectory("scene_editor_quit");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const std::string asked = "firn view: " + scene.string() + " has changes not saved";
  const fs::path saving = writeScene(folder, "save.json", R"([
    {"frame": 3, "click": "/bodies/0#duplicate"},
    {"frame": 5, "click": "#undo"},
    {"frame": 7, "click": "#redo"},
    {"frame": 9, "close": true},
    {"frame": 12, "click": "#cancel"},
    {"frame": 15, "close": true},
    {"frame": 18, "click": "#save-and-quit"}])");
  const Result saved = edit(scene, saving, 400);
  ASSERT_EQ(saved.exitCode, 0) << saved.output;
  EXPECT_EQ(stepsTaken(saved.output), -1) << "the window ran its 400 frames: " << saved.output;
  const std::size_t first = saved.output.find(asked);
  ASSERT_NE(first, std::string::npos) << saved.output;
  EXPECT_NE(saved.output.find(asked, first + 1), std::string::npos) << "asked once, not again after Cancel";
  Json twoBodies = Json::parse(kBallScene);
  twoBodies["bodies"].push_back(twoBodies["bodies"][0]);
  EXPECT_EQ(readJson(scene), twoBodies) << saved.output;

  const std::string before = firn::readRegularFile(scene, "scene", 1 << 20);
  const fs::path discarding = writeScene(folder, "discard.json", R"([
    {"frame": 3, "click": "/bodies/1#delete"},
    {"frame": 5, "close": true},
    {"frame": 8, "click": "#quit-without-saving"}])");
  const Result discarded = edit(scene, discarding, 400);
  ASSERT_EQ(discarded.exitCode, 0) << discarded.output;
  EXPECT_NE(discarded.output.find(asked), std::string::npos) << discarded.output;
  EXPECT_EQ(stepsTaken(discarded.output), -1) << discarded.output;
  EXPECT_EQ(firn::readRegularFile(scene, "scene", 1 << 20), before);
}

// A ball of snow and a rigid box seen square-on from 2 m (h = 0.05 m: at that distance 0.1 m is about 50 pixels).
const char* const kTwoPartsScene = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 2 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.45, 0.6, 0.6], "radius": 0.1, "material": "snow" } ],
  "rigid_bodies": [ { "shape": "box", "center": [0.8, 0.6, 0.6], "size": [0.1, 0.1, 0.1], "density": 500 } ],
  "camera": { "position": [0.6, 0.6, 2.6], "target": [0.6, 0.6, 0.6], "fov_deg": 40 } })";

// The window `edit` opens is 1000 × 720 pixels, the panel 460 wide: the view is the 540 × 720 beside it.
constexpr float kPanelPx = 460, kViewWidthPx = 540, kViewHeightPx = 720;

// Where the scene's camera shows a point in the window, as the editor's view projects it.
glm::vec2 windowPixel(const firn::Scene& scene, const glm::dvec3& pointM) {
  const float aspect = kViewWidthPx / kViewHeightPx;
  const firn::render::Camera camera = firn::render::defaultCamera(scene, aspect);
  const glm::dvec4 clip =
      glm::dmat4(camera.projection(aspect)) * glm::dmat4(camera.view()) * glm::dvec4(pointM, 1.0);
  return {kPanelPx + float((clip.x / clip.w * 0.5 + 0.5) * kViewWidthPx),
          float((0.5 - clip.y / clip.w * 0.5) * kViewHeightPx)};
}

std::string pixelJson(const glm::vec2& px) { return "[" + std::to_string(px.x) + ", " + std::to_string(px.y) + "]"; }

// A click at a pixel of the window (a press and a release a frame later) with `button`.
std::string clickAt(int frame, const glm::vec2& px, const std::string& button) {
  return R"({"frame": )" + std::to_string(frame) + R"(, "mouse": )" + pixelJson(px) + R"(, "button": ")" + button +
         R"(", "action": "press"}, {"frame": )" + std::to_string(frame + 1) + R"(, "mouse": )" + pixelJson(px) +
         R"(, "button": ")" + button + R"(", "action": "release"})";
}

// From the scene's own camera: a click on the rigid box picks it and its y handle drags it up 0.1 m; a click on the
// ball picks it and its x handle drags it 0.1 m along x (snapped to the 0.05 m cells, so a drag of about 0.1 m is
// exactly 0.1 m); a right-click where nothing is adds a rigid mesh from the file dialog at the point the ray reaches
// at the camera's distance to its target. The saved file is the scene with those three changes and no other.
TEST(SceneEditor, PicksDragsAndAddsPartsInTheView) {
  const fs::path folder = freshDirectory("scene_editor_view");
  const fs::path scene = writeScene(folder, "two.json", kTwoPartsScene);
  // A closed cube of 0.1 m about its origin, faces wound outwards.
  writeScene(folder, "cube.obj", R"(v -0.05 -0.05 -0.05
v 0.05 -0.05 -0.05
v 0.05 0.05 -0.05
v -0.05 0.05 -0.05
v -0.05 -0.05 0.05
v 0.05 -0.05 0.05
v 0.05 0.05 0.05
v -0.05 0.05 0.05
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
)");
  const firn::Scene loaded = firn::parseScene(kTwoPartsScene, scene);
  const glm::vec2 box = windowPixel(loaded, {0.8, 0.6, 0.6});
  const glm::vec2 boxUp = windowPixel(loaded, {0.8, 0.7, 0.6}) - box;
  const glm::vec2 ball = windowPixel(loaded, {0.45, 0.6, 0.6});
  const glm::vec2 ballAlong = windowPixel(loaded, {0.55, 0.6, 0.6}) - ball;
  const glm::vec2 empty = windowPixel(loaded, {0.6, 0.9, 0.6});
  const fs::path events = writeScene(folder, "events.json", "[" + std::string(R"({"frame": 3, "click": "#snap"}, )") +
      clickAt(5, box, "left") + R"(, {"frame": 8, "drag": "#handle-y", "by": )" + pixelJson(boxUp) + "}, " +
      clickAt(14, ball, "left") + R"(, {"frame": 17, "drag": "#handle-x", "by": )" + pixelJson(ballAlong) + "}, " +
      clickAt(23, empty, "right") + R"(, {"frame": 26, "click": "#add-here/rigid_bodies/mesh"},
      {"frame": 29, "click": "#file/cube.obj"}, {"frame": 33, "key": "S", "mods": ["ctrl"]}])");
  const Result result = edit(scene, events, 60);
  ASSERT_EQ(result.exitCode, 0) << result.output;

  Json expected = Json::parse(kTwoPartsScene);
  expected["bodies"][0]["center"] = {0.55, 0.6, 0.6};
  expected["rigid_bodies"][0]["center"] = {0.8, 0.7, 0.6};
  // The camera's ray through that pixel, 2 m out (its distance to its target), snapped: (0.6, 0.897, 0.622) → cells.
  expected["rigid_bodies"].push_back({{"shape", "mesh"}, {"path", "cube.obj"}, {"translate", {0.6, 0.9, 0.6}},
                                      {"density", 917}});
  EXPECT_EQ(readJson(scene), expected) << result.output;
}

// While the scene runs in the window, a material's slider changes it at the next step (Simulation::setMaterials): a
// press at the middle of Poisson's ratio's slider, [0, 0.49], sets ν ≈ 0.245, and the run goes on (ν 0.2 → 0.245
// makes the wave 3.4% faster: the 1 ms step stays within its 2.2 ms bound); the saved file holds the value.
TEST(SceneEditor, MaterialsEditedWhileRunningApplyAtTheNextStep) {
  const fs::path folder = freshDirectory("scene_editor_live");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const fs::path events = writeScene(folder, "events.json", R"([
    {"frame": 3, "key": "TAB"},
    {"frame": 10, "drag": "/materials/snow#slider-poisson_ratio", "by": [0, 0]},
    {"frame": 40, "key": "S", "mods": ["ctrl"]}])");
  const Result result = edit(scene, events, 60);
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_NE(result.output.find("firn view: The materials as edited apply from t = "), std::string::npos)
      << result.output;
  EXPECT_GT(stepsTaken(result.output), 0) << result.output;
  // The slider's middle in pixels, as ImGui lays out its grab: 0.245 to a few pixels of the 0.49 across ~270 px.
  Json saved = readJson(scene);
  ASSERT_TRUE(saved["materials"]["snow"].contains("poisson_ratio")) << saved.dump();
  EXPECT_NEAR(saved["materials"]["snow"]["poisson_ratio"].get<double>(), 0.245, 0.01);
  saved["materials"]["snow"].erase("poisson_ratio");
  EXPECT_EQ(saved, Json::parse(kBallScene));
}

// "Run headless" hands the scene, saved first, to `firn run` in a process of its own, with the usual outputs in the
// folder the panel names (SCENE's stem + "_out" beside it); a scripted window waits for it to end and says how it
// ended. The edit leaves the ball scene 1 frame at 50 per second, 20 steps of 1 ms: frames 0 and 1 on disk.
TEST(SceneEditor, RunsTheEditedSceneHeadless) {
  const fs::path folder = freshDirectory("scene_editor_headless");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const fs::path events = writeScene(folder, "events.json", R"([
    {"frame": 3, "click": "/time/frames"},
    {"frame": 4, "key": "A", "mods": ["ctrl"]},
    {"frame": 5, "text": "1"},
    {"frame": 6, "key": "ENTER"},
    {"frame": 8, "click": "#headless"},
    {"frame": 10, "click": "#run-headless"}])");
  const Result result = edit(scene, events, 14);
  ASSERT_EQ(result.exitCode, 0) << result.output;
  // The edit (1 frame, not 2) reached the file before the run took it.
  EXPECT_EQ(readJson(scene)["time"]["frames"], 1) << result.output;
  const fs::path out = folder / "ball_out";
  EXPECT_NE(result.output.find("firn view: running headless: firn run " + scene.string() + " --out " + out.string()),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("firn view: the headless run ended (exit 0): firn: wrote 2 frames (2167 particles, 20 "
                               "steps)"),
            std::string::npos)
      << result.output;
  for (const char* file : {"run.json", "stats.csv", "frame_0000.ply", "frame_0001.ply"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
  EXPECT_FALSE(fs::exists(out / "frame_0002.ply"));
}

// A scene file that does not exist yet is begun from Firn's built-in scene and saved there. Edits that take parts away
// leave nothing dangling: a sphere added (and selected), undone, then Ctrl+D on the selection the undo took away; the
// last section removed while the panel draws it. The file saved is the built-in scene without its camera.
TEST(SceneEditor, BeginsANewSceneAndSurvivesEditsThatTakePartsAway) {
  const fs::path folder = freshDirectory("scene_editor_new");
  const fs::path scene = folder / "new.json";
  const fs::path events = writeScene(folder, "events.json", R"([
    {"frame": 3, "click": "/bodies#add-sphere"},
    {"frame": 6, "click": "#undo"},
    {"frame": 8, "key": "D", "mods": ["ctrl"]},
    {"frame": 10, "click": "/camera#remove"},
    {"frame": 13, "key": "S", "mods": ["ctrl"]}])");
  const Result result = edit(scene, events, 40);
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_NE(result.output.find("firn view: " + scene.string() + " does not exist yet"), std::string::npos)
      << result.output;
  Json expected = readJson(fs::path(FIRN_SOURCE_DIR) / "assets/scenes/snowball_wall.json");
  expected.erase("camera");
  ASSERT_TRUE(fs::exists(scene)) << result.output;
  EXPECT_EQ(readJson(scene), expected) << result.output;
}

// A scene the loader and the pre-flight take but the window cannot start (a surface its particles do not suit, with
// --render surface) stays the panel's problem: each document tried once (the two edits make one or two, as they
// settle together or apart), not again frame after frame, and the window goes on.
TEST(SceneEditor, ASceneTheWindowCannotStartIsTriedOnce) {
  const fs::path folder = freshDirectory("scene_editor_unstartable");
  const std::string ball = kBallScene;
  const fs::path scene = writeScene(folder, "surface.json", ball.substr(0, ball.rfind('}')) +
                                                                R"(, "surface": { "resolution": 2, "smoothing": 3 } })");
  const fs::path events = writeScene(folder, "events.json", R"([
    {"frame": 3, "click": "/surface/resolution"}, {"frame": 4, "key": "A", "mods": ["ctrl"]},
    {"frame": 5, "text": "8"}, {"frame": 6, "key": "ENTER"},
    {"frame": 8, "click": "/surface/smoothing"}, {"frame": 9, "key": "A", "mods": ["ctrl"]},
    {"frame": 10, "text": "6"}, {"frame": 11, "key": "ENTER"}])");
  const Result result = edit(scene, events, 40, " --render surface");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const std::size_t refusals = linesAfter(result.output, "firn view: cannot run: ").size();
  EXPECT_GE(refusals, 1u) << result.output;
  EXPECT_LE(refusals, 2u) << result.output;
  EXPECT_NE(result.output.find("firn view: 40 frames"), std::string::npos) << result.output;
}

// A script that does not fit the editor, or is not a script, is bad input (exit 2) that names the file and the event.
TEST(SceneEditor, ReplayedInputThatDoesNotFitIsBadInput) {
  const fs::path folder = freshDirectory("scene_editor_bad_events");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const fs::path unknownKey = writeScene(folder, "key.json", R"([{"frame": 2, "key": "F13"}])");
  const Result key = edit(scene, unknownKey, 10);
  EXPECT_EQ(key.exitCode, 2) << key.output;
  EXPECT_NE(key.output.find(unknownKey.string() + ": events[0].key: is not a key an event may name"), std::string::npos)
      << key.output;
  const fs::path missingField = writeScene(folder, "field.json", R"([{"frame": 2, "click": "/bodies/7/radius"}])");
  const Result field = edit(scene, missingField, 10);
  EXPECT_EQ(field.exitCode, 2) << field.output;
  const std::string notDrawn =
      "--replay: the event at frame 2 clicks \"/bodies/7/radius\", which the editor did not draw";
  EXPECT_NE(field.output.find(notDrawn), std::string::npos)
      << field.output;
}

// The window's panel prints the numbers it shows (run/SimulationSession.h, numbersBeforeRunning) under "firn view:
// before running:"; they are `firn run`'s start for the same scene, word for word.
TEST(SceneEditor, ShowsTheNumbersFirnRunStartsWith) {
  const fs::path folder = freshDirectory("scene_editor_numbers");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const fs::path events = writeScene(folder, "events.json", "[]");
  const Result view = edit(scene, events, 2);
  ASSERT_EQ(view.exitCode, 0) << view.output;
  const Result run = runFirn("run " + scene.string() + " --check");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const std::vector<std::string> viewLines = linesAfter(view.output, "firn view: ");
  const auto shown = std::find(viewLines.begin(), viewLines.end(), "before running:");
  ASSERT_NE(shown, viewLines.end()) << view.output;
  const std::vector<std::string> runLines = linesAfter(run.output, "firn: ");
  ASSERT_GT(runLines.size(), 3u) << run.output;
  // The opening line up to the renderer (a window's context names it as it likes), then each note and warning.
  ASSERT_GT(viewLines.end() - shown, 3) << view.output;
  EXPECT_EQ(shown[1].substr(0, shown[1].find(" on ")), runLines[0].substr(0, runLines[0].find(" on ")));
  for (std::size_t i = 1; i < 4; ++i) EXPECT_EQ(shown[std::ptrdiff_t(i) + 1], runLines[i]);
  // And how fast it steps here, timed from its start before it runs.
  const std::vector<std::string> timed = linesAfter(view.output, "firn view: a step of 2,167 particles took ");
  ASSERT_EQ(timed.size(), 1u) << view.output;
  EXPECT_GT(std::stod(timed[0]), 0.0) << timed[0];
}

// And for every scene Firn ships: the panel's numbers (numbersBeforeRunning, as `firn run` would start) equal the
// lines `firn run --check` prints before its transfers' timing.
TEST(SceneEditor, NumbersBeforeRunningAreFirnRunsForEveryShippedScene) {
  for (const fs::directory_entry& entry : fs::directory_iterator(fs::path(FIRN_SOURCE_DIR) / "assets/scenes")) {
    if (entry.path().extension() != ".json") continue;
    const firn::Scene scene = firn::loadScene(entry.path());
    firn::SessionOptions options;
    options.lastFrame = scene.time.frames;
    const firn::StartNumbers numbers = firn::numbersBeforeRunning(scene, firn::test::glContext().info(), options);
    const Result run = runFirn("run " + entry.path().string() + " --check");
    ASSERT_EQ(run.exitCode, 0) << run.output;
    const std::vector<std::string> runLines = linesAfter(run.output, "firn: ");
    ASSERT_GT(runLines.size(), numbers.lines.size()) << run.output;
    for (std::size_t i = 0; i < numbers.lines.size(); ++i) {
      EXPECT_EQ(numbers.lines[i], runLines[i]) << entry.path();
    }
  }
}

}  // namespace
