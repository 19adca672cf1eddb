#include "scene/PartTransforms.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/trigonometric.hpp>

namespace firn {
namespace {

// A part's shape word: a body's or rigid body's "shape", a collider's "type".
std::string shapeOf(const json::Json& part) {
  for (const char* key : {"shape", "type"}) {
    if (part.contains(key) && part[key].is_string()) return part[key].get<std::string>();
  }
  return "";
}

bool isPlaced(const json::Json& part) {
  const std::string shape = shapeOf(part);
  return shape == "mesh" || shape == "points";
}

// A vec3 key's numbers, or `fallback` where the key is absent or not three numbers (the loader names that).
glm::dvec3 vec3Of(const json::Json& part, const char* key, const glm::dvec3& fallback) {
  if (!part.contains(key)) return fallback;
  const json::Json& value = part[key];
  if (!value.is_array() || value.size() != 3) return fallback;
  for (const json::Json& component : value) {
    if (!component.is_number()) return fallback;
  }
  return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

// Sets a vec3 key that holds three numbers; leaves one that does not (the loader's message stays).
void addTo(json::Json& part, const char* key, const glm::dvec3& deltaM) {
  const glm::dvec3 none(std::nan(""));
  const glm::dvec3 value = vec3Of(part, key, none);
  if (!std::isnan(value.x)) part[key] = fileVector(value + deltaM);
}

// R = R_z(γ) R_y(β) R_x(α) of `rotate_deg` = (α, β, γ) (docs/scene-format.md).
glm::dmat3 rotationZyx(const glm::dvec3& degrees) {
  const glm::dvec3 r = glm::radians(degrees);
  const glm::dmat4 rz = glm::rotate(glm::dmat4(1.0), r.z, glm::dvec3(0, 0, 1));
  const glm::dmat4 ry = glm::rotate(glm::dmat4(1.0), r.y, glm::dvec3(0, 1, 0));
  const glm::dmat4 rx = glm::rotate(glm::dmat4(1.0), r.x, glm::dvec3(1, 0, 0));
  return glm::dmat3(rz * ry * rx);
}

// The angles (α, β, γ) in degrees of R = R_z(γ) R_y(β) R_x(α): R's third row is (−sin β, cos β sin α, cos β cos α)
// and its first column cos β (cos γ, sin γ, ·). At β = ±90° only α ∓ γ is defined: α is taken as 0.
glm::dvec3 eulerZyxDeg(const glm::dmat3& rotation) {
  // glm's matrices are column-major: rotation[c][r] is row r of column c.
  const double sinBeta = std::clamp(-rotation[0][2], -1.0, 1.0);
  const double beta = std::asin(sinBeta);
  double alpha = 0, gamma = 0;
  if (std::abs(sinBeta) < 1 - 1e-12) {
    alpha = std::atan2(rotation[1][2], rotation[2][2]);
    gamma = std::atan2(rotation[0][1], rotation[0][0]);
  } else {
    gamma = std::atan2(-rotation[1][0], rotation[1][1]);
  }
  return glm::degrees(glm::dvec3(alpha, beta, gamma));
}

}  // namespace

json::Json movedPart(const json::Json& part, const glm::dvec3& deltaM) {
  json::Json moved = part;
  for (const char* key : {"center", "point", "pivot", "min", "max"}) addTo(moved, key, deltaM);
  if (isPlaced(part)) moved["translate"] = fileVector(vec3Of(part, "translate", glm::dvec3(0.0)) + deltaM);
  return moved;
}

bool partTurns(const json::Json& part, const std::string& section) {
  const std::string shape = shapeOf(part);
  if (shape == "mesh") return true;
  if (shape == "points") return section == "bodies";
  return shape == "box" && section == "rigid_bodies";
}

json::Json turnedPart(const json::Json& part, int axis, double degrees, const glm::dvec3& pivotM) {
  json::Json turned = part;
  glm::dvec3 worldAxis(0.0);
  worldAxis[axis] = 1;
  const glm::dmat3 turn = glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(degrees), worldAxis));
  const glm::dvec3 rotationDeg = vec3Of(part, "rotate_deg", glm::dvec3(0.0));
  turned["rotate_deg"] = fileVector(eulerZyxDeg(turn * rotationZyx(rotationDeg)));
  if (isPlaced(part)) {
    turned["translate"] = fileVector(pivotM + turn * (vec3Of(part, "translate", glm::dvec3(0.0)) - pivotM));
  }
  const glm::dvec3 none(std::nan(""));
  const glm::dvec3 centerM = vec3Of(part, "center", none);
  if (!std::isnan(centerM.x)) turned["center"] = fileVector(pivotM + turn * (centerM - pivotM));
  return turned;
}

bool partScales(const json::Json& part) { return shapeOf(part) != "plane"; }

json::Json scaledPart(const json::Json& part, double factor, const glm::dvec3& pivotM) {
  json::Json scaled = part;
  if (part.contains("radius") && part["radius"].is_number()) {
    scaled["radius"] = fileNumber(part["radius"].get<double>() * factor);
  }
  const glm::dvec3 none(std::nan(""));
  const glm::dvec3 size = vec3Of(part, "size", none);
  if (!std::isnan(size.x)) scaled["size"] = fileVector(size * factor);
  const glm::dvec3 minM = vec3Of(part, "min", none), maxM = vec3Of(part, "max", none);
  if (!std::isnan(minM.x) && !std::isnan(maxM.x)) {
    const glm::dvec3 middle = 0.5 * (minM + maxM), half = 0.5 * (maxM - minM) * factor;
    scaled["min"] = fileVector(middle - half);
    scaled["max"] = fileVector(middle + half);
  }
  if (isPlaced(part)) {
    const double scale = part.contains("scale") && part["scale"].is_number() ? part["scale"].get<double>() : 1.0;
    scaled["scale"] = fileNumber(scale * factor);
    // p' = translate + R (scale · p): the file's origin sits at `translate`, and moves with the scaling about the pivot.
    scaled["translate"] = fileVector(pivotM + factor * (vec3Of(part, "translate", glm::dvec3(0.0)) - pivotM));
  }
  return scaled;
}

double fileNumber(double value) { return std::round(value * 1e9) / 1e9; }

json::Json fileVector(const glm::dvec3& value) {
  return json::Json::array({fileNumber(value.x), fileNumber(value.y), fileNumber(value.z)});
}

double snapTo(double value, double step) { return std::round(value / step) * step; }

}  // namespace firn
