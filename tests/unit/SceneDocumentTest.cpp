// The scene editor's model (scene/SceneDocument.h): every shipped scene saved elsewhere loads to the same scene (the
// same fingerprint: grid, step, materials, colliders and bodies with their fields, every particle); edits undo and
// redo to the byte; a bad value is the loader's own message, naming the key; nothing is saved while it stands.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Error.h"
#include "gpu/Materials.h"
#include "scene/SceneDocument.h"
#include "sim/SceneUpload.h"
#include "support/TestFiles.h"

namespace firn {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(FIRN_SOURCE_DIR) / "assets" / "scenes";

std::uint64_t fingerprintOf(const Scene& scene) {
  const std::vector<ParticleSeed> seeds = sampleBodies(scene);
  return sceneFingerprint(scene, seeds.size(), buildMaterialTable(scene), bakeColliderFields(scene), seeds);
}

// A shipped scene copied into a test folder, so that edits and saves stay there.
SceneDocument copyOf(const std::string& name, const std::filesystem::path& folder) {
  const std::filesystem::path copy = folder / name;
  std::filesystem::copy_file(kScenes / name, copy);
  return SceneDocument::open(copy);
}

TEST(SceneDocument, EveryShippedSceneSavedElsewhereLoadsToTheSameScene) {
  // Saved one folder deeper, its meshes' paths are rewritten for the new folder; the text is the editor's own.
  const std::filesystem::path folder = test::freshDirectory("document_round_trip") / "saved";
  std::filesystem::create_directories(folder);
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().filename().string());
    SceneDocument document = SceneDocument::open(entry.path());
    const std::filesystem::path saved = folder / entry.path().filename();
    document.save(saved);
    EXPECT_FALSE(document.modified());
    EXPECT_EQ(document.path(), saved);
    EXPECT_EQ(fingerprintOf(loadScene(saved)), fingerprintOf(loadScene(entry.path())));
    EXPECT_EQ(SceneDocument::open(saved).text(), test::fileBytes(saved));  // saved again, the same bytes
    ++scenes;
  }
  EXPECT_GE(scenes, 15);
}

TEST(SceneDocument, EditsUndoAndRedoToTheByte) {
  const std::filesystem::path folder = test::freshDirectory("document_edits");
  SceneDocument document = copyOf("paddle_drum.json", folder);
  const std::string original = document.text();
  document.set("/bodies/0/max/1", 0.3);           // a number in a vec3
  document.set("/bodies/0/mass_scale", 2);         // a key the body did not have: after its last
  document.remove("/colliders/1/boundary");        // a key in the middle of its object
  document.remove("/colliders/0");                 // an element: the others move up
  document.insert("/colliders", 1, {{"type", "sphere"}, {"center", {0.3, 0.4, 0.5}}, {"radius", 0.05}});
  EXPECT_TRUE(document.modified());
  EXPECT_EQ(document.json()["bodies"][0]["max"][1], 0.3);
  EXPECT_EQ(std::prev(document.json()["bodies"][0].end()).key(), "mass_scale");
  EXPECT_EQ(document.json()["colliders"][1]["type"], "sphere");
  const std::string edited = document.text();
  while (document.canUndo()) document.undo();
  EXPECT_EQ(document.text(), original);  // the removed key back in its place, the element at its index
  EXPECT_FALSE(document.modified());
  while (document.canRedo()) document.redo();
  EXPECT_EQ(document.text(), edited);
  // An edit after an undo drops what was undone.
  document.undo();
  document.set("/name", "stirred");
  EXPECT_FALSE(document.canRedo());
  EXPECT_THROW(document.set("/no_such_section/key", 1), std::invalid_argument);
  EXPECT_THROW(document.set("/colliders/9", 1), std::invalid_argument);
  EXPECT_THROW(document.remove("colliders/0"), std::invalid_argument);  // no leading "/"
}

TEST(SceneDocument, ABadValueIsTheLoadersProblemAndIsNotSaved) {
  const std::filesystem::path folder = test::freshDirectory("document_problem");
  SceneDocument document = copyOf("snowball_wall.json", folder);
  EXPECT_FALSE(document.problem());
  document.set("/bodies/0/radius", -0.1);
  const std::optional<SceneDocument::Problem> problem = document.problem();
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->keyPath, "bodies[0].radius");
  // The message is the loader's, word for word.
  std::string loaders;
  try {
    parseScene(document.json().dump(), document.path());
  } catch (const InputError& error) {
    loaders = error.what();
  }
  EXPECT_EQ(problem->message, loaders);
  EXPECT_NE(loaders.find("bodies[0].radius: must be greater than 0 (got -0.1)"), std::string::npos) << loaders;
  EXPECT_THROW(document.save(folder / "bad.json"), InputError);
  EXPECT_FALSE(std::filesystem::exists(folder / "bad.json"));
  document.undo();
  EXPECT_FALSE(document.problem());
  // An unknown key is the loader's too, with its suggestion.
  document.set("/bodies/0/raduis", 0.1);
  ASSERT_TRUE(document.problem());
  EXPECT_EQ(document.problem()->keyPath, "bodies[0].raduis");
  EXPECT_NE(document.problem()->message.find("radius"), std::string::npos) << document.problem()->message;
}

TEST(SceneDocument, SavingMakesItUnmodifiedUntilTheNextEdit) {
  const std::filesystem::path folder = test::freshDirectory("document_saved");
  SceneDocument document = copyOf("snowball_wall.json", folder);
  document.set("/time/frames", 12);
  document.save(folder / "twelve.json");
  EXPECT_FALSE(document.modified());
  EXPECT_EQ(loadScene(folder / "twelve.json").time.frames, 12);
  document.undo();  // back before the save: modified again, and saved to a different file
  EXPECT_TRUE(document.modified());
  document.set("/time/frames", 13);  // the saved state can no longer be reached
  document.undo();
  EXPECT_TRUE(document.modified());
}

// The keys an object may hold, as the loader lists them: what the editor offers to add.
TEST(SceneDocument, KnowsTheKeysEachObjectAllows) {
  const std::filesystem::path folder = test::freshDirectory("document_keys");
  const SceneDocument document = copyOf("snowball_wall.json", folder);
  EXPECT_EQ(document.keysAllowedAt("/grid"), (std::vector<std::string>{"origin", "cells", "cell_size"}));
  const std::vector<std::string> sphere = document.keysAllowedAt("/bodies/0");
  for (const char* key : {"shape", "center", "radius", "material", "velocity", "particles_per_cell"}) {
    EXPECT_NE(std::find(sphere.begin(), sphere.end(), key), sphere.end()) << key;
  }
  EXPECT_EQ(std::find(sphere.begin(), sphere.end(), "min"), sphere.end()) << "a box's key, not a sphere's";
  // The materials' keys are names, and a key that is not an object holds none.
  EXPECT_TRUE(document.keysAllowedAt("/materials").empty());
  EXPECT_TRUE(document.keysAllowedAt("/grid/cells").empty());
}

}  // namespace
}  // namespace firn
