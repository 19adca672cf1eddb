#pragma once
// Moving, turning and resizing a part of a scene file — a body, a collider, a rigid body — by the keys the file
// writes it with (docs/scene-format.md): the scene editor's handles (apps/firn/SceneEditor.h) edit a part's object
// with these, so a sphere moves by its `center`, a snow box by its `min` and `max`, a plane by its `point`, a mesh
// by its `translate`; keys the change does not concern keep their values and places.
#include <string>

#include <glm/vec3.hpp>

#include "scene/JsonChecker.h"

namespace firn {

// The part moved by `deltaM`: its `center`, `point`, `pivot`, `min` and `max` where it has them, and a mesh's or points
// body's `translate` (added as `deltaM` where the file leaves it out). A collider's keyframes are displacements from
// its rest, so they move with it.
json::Json movedPart(const json::Json& part, const glm::dvec3& deltaM);

// Whether the scene file lets the part turn: a mesh or points body, a mesh collider, a rigid box or mesh (their
// `rotate_deg`). A sphere, a snow or collider box (axis-aligned) and a plane do not.
bool partTurns(const json::Json& part, const std::string& section);
// The part turned by `degrees` about the world's axis `axis` (0 x, 1 y, 2 z) through `pivotM`: its `rotate_deg`
// (R = R_z R_y R_x) becomes that of R_axis R, and its placement (`center`, a mesh's `translate`) turns about the pivot.
json::Json turnedPart(const json::Json& part, int axis, double degrees, const glm::dvec3& pivotM);

// Whether the part has a size to scale: all but a plane.
bool partScales(const json::Json& part);
// The part scaled by `factor` about `pivotM`: a sphere's `radius` and a box's `size` (about their centre, the pivot
// the editor gives them), a box's `min` and `max` about their middle, a mesh's or points body's `scale` with its
// `translate` drawn towards the pivot or away from it.
json::Json scaledPart(const json::Json& part, double factor, const glm::dvec3& pivotM);

// A number a change computed, as the file should read it: to 1e-9 (a nanometre, a nanodegree), so that 0.6 + 0.1
// writes 0.7 and not the sum's 0.7000000000000001.
double fileNumber(double value);

// A point or vector as the file writes it: three numbers, each a fileNumber.
json::Json fileVector(const glm::dvec3& value);

// `value` to the nearest multiple of `step` (step > 0).
double snapTo(double value, double step);

}  // namespace firn
