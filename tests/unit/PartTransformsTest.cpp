// The scene editor's moves, turns and resizes of a part (scene/PartTransforms.h): by the keys the file writes the part
// with, the other keys left as they were, and the numbers written as a user would type them.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

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

TEST(PartTransforms, TurnsWhatTheFileLetsTurn) {
  const Json rigidBox =
      Json::parse(R"({"shape": "box", "center": [0.5, 0.6, 0.5], "size": [0.2, 0.1, 0.3], "density": 600})");
  EXPECT_TRUE(partTurns(rigidBox, "rigid_bodies"));
  EXPECT_FALSE(partTurns(rigidBox, "bodies"));  // a snow box is axis-aligned (min, max)
  EXPECT_FALSE(partTurns(Json::parse(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1})"), "colliders"));
  EXPECT_FALSE(partTurns(Json::parse(R"({"shape": "points", "path": "p.ply"})"), "rigid_bodies"));
  EXPECT_TRUE(partTurns(Json::parse(R"({"shape": "points", "path": "p.ply"})"), "bodies"));
  // About its own centre, the pivot the editor gives a rigid box: it stays where it is.
  const glm::dvec3 centre(0.5, 0.6, 0.5);
  const Json twice = turnedPart(turnedPart(rigidBox, 1, 30, centre), 1, 15, centre);
  EXPECT_EQ(twice["rotate_deg"], Json::parse("[0, 45, 0]"));
  EXPECT_EQ(twice["center"], rigidBox["center"]);
  // A turn about world z after R_x: the outermost of R_z R_y R_x, so the angles simply add.
  const Json turned = Json::parse(R"({"type": "mesh", "path": "rock.obj", "rotate_deg": [90, 0, 0]})");
  EXPECT_EQ(turnedPart(turned, 2, -10, glm::dvec3(0.0))["rotate_deg"], Json::parse("[90, 0, -10]"));
}

// A turn about world x of a mesh already turned about z (the sled's [0, 0, −20]) is R_x(10°) R_z(−20°), not the
// angles [10, 0, −20] (which would be R_z R_x, a turn about the part's own tilted x): the angles written give that
// matrix back, and the mesh's origin turns about the pivot.
TEST(PartTransforms, TurnsAboutTheWorldsAxisThroughThePivot) {
  const Json sled = Json::parse(R"({"shape": "mesh", "path": "sled.obj", "rotate_deg": [0, 0, -20],
                                    "translate": [0.2, 0.6, 0.2], "density": 2000})");
  const glm::dvec3 pivot(0.3, 0.6, 0.2);
  const Json turned = turnedPart(sled, 0, 10, pivot);
  const auto rotationOf = [](const Json& degrees) {
    const glm::dvec3 r = glm::radians(glm::dvec3(degrees[0].get<double>(), degrees[1].get<double>(),
                                                 degrees[2].get<double>()));
    return glm::rotate(glm::dmat4(1.0), r.z, glm::dvec3(0, 0, 1)) * glm::rotate(glm::dmat4(1.0), r.y, glm::dvec3(0, 1, 0)) *
           glm::rotate(glm::dmat4(1.0), r.x, glm::dvec3(1, 0, 0));
  };
  const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), glm::radians(10.0), glm::dvec3(1, 0, 0));
  const glm::dmat4 expected = turn * rotationOf(sled["rotate_deg"]);
  const glm::dmat4 written = rotationOf(turned["rotate_deg"]);
  // The angles are written to 1e-9°: the matrices agree to about 2e-11.
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(written[c][r], expected[c][r], 1e-10) << c << " " << r;
  }
  // The origin (0.2, 0.6, 0.2) is 0.1 m from the pivot along −x, on the axis: it stays.
  EXPECT_EQ(turned["translate"], sled["translate"]);
  const Json offAxis = turnedPart(sled, 2, 90, pivot);  // about z: (−0.1, 0, 0) from the pivot goes to (0, −0.1, 0)
  EXPECT_EQ(offAxis["translate"], Json::parse("[0.3, 0.5, 0.2]"));
}

TEST(PartTransforms, ScalesSizesAboutTheMiddle) {
  const Json sphere = Json::parse(R"({"shape": "sphere", "center": [0.6, 0.45, 0.48], "radius": 0.12})");
  EXPECT_EQ(scaledPart(sphere, 1.5, glm::dvec3(0.6, 0.45, 0.48))["radius"], Json(0.18));
  const Json box = Json::parse(R"({"type": "box", "min": [0.1, 0.1, 0.1], "max": [0.3, 0.2, 0.4]})");
  const Json doubled = scaledPart(box, 2, glm::dvec3(0.2, 0.15, 0.25));
  EXPECT_EQ(doubled["min"], Json::parse("[0.0, 0.05, -0.05]"));
  EXPECT_EQ(doubled["max"], Json::parse("[0.4, 0.25, 0.55]"));
  EXPECT_EQ(scaledPart(Json::parse(R"({"shape": "box", "size": [0.2, 0.1, 0.3]})"), 0.5, glm::dvec3(0.0))["size"],
            Json::parse("[0.1, 0.05, 0.15]"));
  // A mesh scales about the pivot: its origin, 0.1 m from it, goes to 0.025 m at a quarter.
  const Json mesh = scaledPart(Json::parse(R"({"shape": "mesh", "path": "m.obj", "translate": [0.4, 0.5, 0.5]})"),
                               0.25, glm::dvec3(0.5, 0.5, 0.5));
  EXPECT_EQ(mesh["scale"], Json(0.25));
  EXPECT_EQ(mesh["translate"], Json::parse("[0.475, 0.5, 0.5]"));
  EXPECT_FALSE(partScales(Json::parse(R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]})")));
  EXPECT_DOUBLE_EQ(snapTo(0.1234, 0.05), 0.1);
  EXPECT_DOUBLE_EQ(snapTo(-0.126, 0.05), -0.15);
}

}  // namespace
}  // namespace firn
