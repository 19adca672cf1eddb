// The scene editor's moves, turns and resizes of a part (scene/PartTransforms.h): by the keys the file writes the part
// with, the other keys left as they were, and the numbers written as a user would type them.
#include <gtest/gtest.h>

#include "scene/PartTransforms.h"

namespace firn {
namespace {

using json::Json;

TEST(PartTransforms, MovesEachPartByTheKeysItIsWrittenWith) {
  const Json sphere =
      Json::parse(R"({"shape": "sphere", "center": [0.6, 0.45, 0.48], "radius": 0.12, "material": "snow"})");
  // 0.6 + 0.1 is 0.7000000000000001 in doubles: the file gets 0.7, what the user dragged to.
  EXPECT_EQ(movedPart(sphere, {0.1, 0, -0.02}),
            Json::parse(R"({"shape": "sphere", "center": [0.7, 0.45, 0.46], "radius": 0.12, "material": "snow"})"));
  const Json box =
      Json::parse(R"({"shape": "box", "min": [0.1, 0.1, 0.1], "max": [0.3, 0.2, 0.4], "material": "snow"})");
  EXPECT_EQ(movedPart(box, {0, 0.05, 0}),
            Json::parse(R"({"shape": "box", "min": [0.1, 0.15, 0.1], "max": [0.3, 0.25, 0.4], "material": "snow"})"));
  const Json plane = Json::parse(R"({"type": "plane", "point": [0, 0.08, 0], "normal": [0, 1, 0]})");
  EXPECT_EQ(movedPart(plane, {0, 0.02, 0}),
            Json::parse(R"({"type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0]})"));
  // A mesh moves by its placement, which a file may leave out; a collider's keyframes are displacements from its rest.
  const Json mesh = Json::parse(R"({"type": "mesh", "path": "rock.obj", "scale": 0.5,
                                    "keyframes": [{"time_s": 0}, {"time_s": 1, "translate": [0.1, 0, 0]}]})");
  EXPECT_EQ(movedPart(mesh, {0.2, 0, 0}),
            Json::parse(R"({"type": "mesh", "path": "rock.obj", "scale": 0.5,
                            "keyframes": [{"time_s": 0}, {"time_s": 1, "translate": [0.1, 0, 0]}],
                            "translate": [0.2, 0, 0]})"));
  // A key that does not hold three numbers is left for the loader to name.
  const Json broken = Json::parse(R"({"shape": "sphere", "center": [0.6, "x", 0.4], "radius": 0.1})");
  EXPECT_EQ(movedPart(broken, {0.1, 0, 0}), broken);
}

TEST(PartTransforms, TurnsWhatTheFileLetsTurnAboutItsOwnAxes) {
  const Json rigidBox =
      Json::parse(R"({"shape": "box", "center": [0.5, 0.6, 0.5], "size": [0.2, 0.1, 0.3], "density": 600})");
  EXPECT_TRUE(partTurns(rigidBox, "rigid_bodies"));
  EXPECT_FALSE(partTurns(rigidBox, "bodies"));  // a snow box is axis-aligned (min, max)
  EXPECT_FALSE(partTurns(Json::parse(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1})"), "colliders"));
  EXPECT_FALSE(partTurns(Json::parse(R"({"shape": "points", "path": "p.ply"})"), "rigid_bodies"));
  EXPECT_TRUE(partTurns(Json::parse(R"({"shape": "points", "path": "p.ply"})"), "bodies"));
  EXPECT_EQ(turnedPart(turnedPart(rigidBox, 1, 30), 1, 15)["rotate_deg"], Json::parse("[0, 45, 0]"));
  const Json turned = Json::parse(R"({"type": "mesh", "path": "rock.obj", "rotate_deg": [90, 0, 0]})");
  EXPECT_EQ(turnedPart(turned, 2, -10)["rotate_deg"], Json::parse("[90, 0, -10]"));
}

TEST(PartTransforms, ScalesSizesAboutTheMiddle) {
  const Json sphere = Json::parse(R"({"shape": "sphere", "center": [0.6, 0.45, 0.48], "radius": 0.12})");
  EXPECT_EQ(scaledPart(sphere, 1.5)["radius"], Json(0.18));
  const Json box = Json::parse(R"({"type": "box", "min": [0.1, 0.1, 0.1], "max": [0.3, 0.2, 0.4]})");
  const Json doubled = scaledPart(box, 2);
  EXPECT_EQ(doubled["min"], Json::parse("[0.0, 0.05, -0.05]"));
  EXPECT_EQ(doubled["max"], Json::parse("[0.4, 0.25, 0.55]"));
  EXPECT_EQ(scaledPart(Json::parse(R"({"shape": "box", "size": [0.2, 0.1, 0.3]})"), 0.5)["size"],
            Json::parse("[0.1, 0.05, 0.15]"));
  EXPECT_EQ(scaledPart(Json::parse(R"({"shape": "mesh", "path": "m.obj"})"), 0.25)["scale"], Json(0.25));
  EXPECT_FALSE(partScales(Json::parse(R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]})")));
  EXPECT_DOUBLE_EQ(snapTo(0.1234, 0.05), 0.1);
  EXPECT_DOUBLE_EQ(snapTo(-0.126, 0.05), -0.15);
}

}  // namespace
}  // namespace firn
