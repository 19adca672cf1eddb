#include "PartHandles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

#include "scene/PartTransforms.h"

namespace firn {
namespace {

constexpr float kArrowPx = 90;       // an arrow's length on screen
constexpr float kPlaneAt = 0.3f;     // a plane's disc, along both its axes, as a fraction of an arrow
constexpr float kHitPx = 8;          // how near a press must fall to a handle
constexpr double kDegreesPerPx = 0.5;
constexpr double kScaleDoublingPx = 140;  // a drag this far right doubles the part's size
constexpr double kSnapDegrees = 15;
const char* const kAxisNames[] = {"x", "y", "z"};
const char* const kPlaneNames[] = {"yz", "zx", "xy"};  // the plane normal to each axis
const ImU32 kAxisColours[] = {IM_COL32(230, 70, 70, 255), IM_COL32(90, 200, 90, 255), IM_COL32(80, 130, 240, 255)};
const ImU32 kActiveColour = IM_COL32(255, 220, 60, 255);
const ImU32 kOutlineColour = IM_COL32(255, 220, 60, 255);

glm::dvec3 unitAxis(int axis) {
  glm::dvec3 e(0.0);
  e[axis] = 1;
  return e;
}

float distanceToSegment(const ImVec2& p, const ImVec2& a, const ImVec2& b) {
  const float dx = b.x - a.x, dy = b.y - a.y;
  const float lengthSquared = dx * dx + dy * dy;
  const float t = lengthSquared > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / lengthSquared, 0.0f, 1.0f) : 0;
  const float ex = a.x + t * dx - p.x, ey = a.y + t * dy - p.y;
  return std::sqrt(ex * ex + ey * ey);
}

float distance(const ImVec2& a, const ImVec2& b) { return std::hypot(a.x - b.x, a.y - b.y); }

// The parameter s of the point anchor + s·axis nearest the ray (the two lines' closest points).
std::optional<double> nearestOnAxis(const render::Ray& ray, const glm::dvec3& anchorM, const glm::dvec3& axis) {
  const glm::dvec3 w = anchorM - ray.originM;
  const double b = glm::dot(axis, ray.direction);
  const double denominator = 1 - b * b;
  if (denominator < 1e-9) return std::nullopt;  // the axis points along the ray
  return (b * glm::dot(ray.direction, w) - glm::dot(axis, w)) / denominator;
}

// Where the ray meets the plane through `anchorM` normal to `normal`.
std::optional<glm::dvec3> meetPlane(const render::Ray& ray, const glm::dvec3& anchorM, const glm::dvec3& normal) {
  const double along = glm::dot(ray.direction, normal);
  if (std::abs(along) < 1e-6) return std::nullopt;
  const double t = glm::dot(anchorM - ray.originM, normal) / along;
  if (t < 0) return std::nullopt;
  return ray.originM + t * ray.direction;
}

// The part's half size: a sphere's radius, else half its bounds' largest extent.
double halfSize(const HandledPart& part) {
  if (part.object.contains("radius") && part.object["radius"].is_number()) return part.object["radius"].get<double>();
  if (!part.boundsM) return 0;
  const glm::dvec3 extent = part.boundsM->second - part.boundsM->first;
  return 0.5 * std::max({extent.x, extent.y, extent.z});
}

}  // namespace

bool ViewCamera::contains(const ImVec2& px) const {
  return px.x >= originPx.x && px.y >= originPx.y && px.x < originPx.x + sizePx.x && px.y < originPx.y + sizePx.y;
}

std::optional<ImVec2> ViewCamera::project(const glm::dvec3& pointM) const {
  const glm::dvec4 clip =
      glm::dmat4(camera.projection(aspect())) * glm::dmat4(camera.view()) * glm::dvec4(pointM, 1.0);
  if (clip.w <= 1e-9) return std::nullopt;
  const double x = clip.x / clip.w, y = clip.y / clip.w;
  return ImVec2(originPx.x + float((x * 0.5 + 0.5) * sizePx.x), originPx.y + float((0.5 - y * 0.5) * sizePx.y));
}

render::Ray ViewCamera::ray(const ImVec2& px) const {
  const glm::dvec2 ndc(2.0 * (px.x - originPx.x) / sizePx.x - 1.0, 1.0 - 2.0 * (px.y - originPx.y) / sizePx.y);
  return render::cameraRay(camera, aspect(), ndc);
}

double ViewCamera::metresPerPixel(const glm::dvec3& pointM) const {
  const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.targetM) - glm::dvec3(camera.positionM));
  const double depthM = std::max(glm::dot(pointM - glm::dvec3(camera.positionM), forward), 1e-6);
  return 2 * depthM * std::tan(glm::radians(double(camera.fovDeg)) / 2) / std::max(double(sizePx.y), 1.0);
}

std::optional<int> PartHandles::hit(const ImVec2& px) const {
  if (!drawn_) return std::nullopt;
  if (planesDrawn_) {
    for (int plane = 0; plane < 3; ++plane) {
      if (distance(px, planesPx_[plane]) < kHitPx + 2) return plane + 3;
    }
  }
  std::optional<int> nearest;
  float nearestPx = kHitPx;
  for (int axis = 0; axis < 3; ++axis) {
    const float d = distanceToSegment(px, anchorPx_, tipsPx_[axis]);
    if (d < nearestPx) {
      nearestPx = d;
      nearest = axis;
    }
  }
  return nearest;
}

bool PartHandles::handleAt(const ImVec2& px) const { return hit(px).has_value(); }

json::Json PartHandles::dragged(const ViewCamera& view, const HandledPart& part, const ImVec2& px, bool snap,
                                double cellSizeM, std::string& change, glm::dvec3& deltaM, double& angleDeg,
                                double& factor) const {
  const Drag& drag = *drag_;
  const render::Ray ray = view.ray(px);
  char text[128];
  deltaM = glm::dvec3(0.0);
  angleDeg = 0;
  factor = 1;
  if (drag.mode == HandleMode::Move) {
    if (drag.axis < 3) {
      const glm::dvec3 axis = unitAxis(drag.axis);
      if (const std::optional<double> s = nearestOnAxis(ray, part.anchorM, axis)) {
        deltaM = (*s - glm::dot(drag.grabM - part.anchorM, axis)) * axis;
      }
    } else if (const std::optional<glm::dvec3> at = meetPlane(ray, part.anchorM, unitAxis(drag.axis - 3))) {
      deltaM = *at - drag.grabM;
      deltaM[drag.axis - 3] = 0;
    }
    if (snap) {
      for (int i = 0; i < 3; ++i) deltaM[i] = snapTo(deltaM[i], cellSizeM);
    }
    std::snprintf(text, sizeof text, "move by (%.4g, %.4g, %.4g) m", deltaM.x, deltaM.y, deltaM.z);
    change = text;
    return movedPart(part.object, deltaM);
  }
  const double acrossPx = double(px.x - drag.pressPx.x);
  if (drag.mode == HandleMode::Turn) {
    angleDeg = acrossPx * kDegreesPerPx;
    if (snap) angleDeg = snapTo(angleDeg, kSnapDegrees);
    std::snprintf(text, sizeof text, "turn by %.4g° about %s", angleDeg, kAxisNames[drag.axis % 3]);
    change = text;
    return turnedPart(part.object, drag.axis % 3, angleDeg, part.anchorM);
  }
  factor = std::exp2(acrossPx / kScaleDoublingPx);
  const double size = halfSize(part);
  if (snap && size > 0) factor = std::max(snapTo(size * factor, 0.5 * cellSizeM), 0.5 * cellSizeM) / size;
  std::snprintf(text, sizeof text, "scale by %.4g", factor);
  change = text;
  return scaledPart(part.object, factor, part.anchorM);
}

std::optional<json::Json> PartHandles::update(const ViewCamera& view, const HandledPart& part, HandleMode mode,
                                              bool snap, double cellSizeM) {
  ImDrawList* draw = ImGui::GetBackgroundDrawList();
  const ImGuiIO& io = ImGui::GetIO();
  targets_.clear();
  drawn_ = planesDrawn_ = false;
  // The selection or the mode changed under the drag: it ends, unmade.
  if (drag_ && (drag_->pointer != part.pointer || drag_->mode != mode)) drag_.reset();
  const std::optional<ImVec2> anchor = view.project(part.anchorM);
  if (!anchor) return std::nullopt;
  const bool turns = partTurns(part.object, part.section), scales = partScales(part.object);
  if ((mode == HandleMode::Turn && !turns) || (mode == HandleMode::Scale && !scales)) return std::nullopt;

  // The handles, a fixed size on screen.
  const double arrowM = kArrowPx * view.metresPerPixel(part.anchorM);
  anchorPx_ = *anchor;
  for (int axis = 0; axis < 3; ++axis) {
    const std::optional<ImVec2> tip = view.project(part.anchorM + arrowM * unitAxis(axis));
    if (!tip) return std::nullopt;
    tipsPx_[axis] = *tip;
    const std::optional<ImVec2> square =
        view.project(part.anchorM + kPlaneAt * arrowM * (unitAxis((axis + 1) % 3) + unitAxis((axis + 2) % 3)));
    if (!square) return std::nullopt;
    planesPx_[axis] = *square;
  }
  drawn_ = true;
  planesDrawn_ = mode == HandleMode::Move;

  // A press on a handle starts a drag; the pointer's travel, the part's change; the release, the edit.
  std::optional<json::Json> edited;
  if (!drag_ && io.MouseClicked[0] && view.contains(io.MousePos) &&
      !ImGui::IsWindowHovered(ImGuiHoveredFlags_AnyWindow)) {
    if (const std::optional<int> handle = hit(io.MousePos)) {
      Drag drag{*handle, mode, io.MousePos, part.anchorM, part.pointer};
      const render::Ray ray = view.ray(io.MousePos);
      if (*handle < 3) {
        const glm::dvec3 axis = unitAxis(*handle);
        drag.grabM = part.anchorM + nearestOnAxis(ray, part.anchorM, axis).value_or(0.0) * axis;
      } else {
        drag.grabM = meetPlane(ray, part.anchorM, unitAxis(*handle - 3)).value_or(part.anchorM);
      }
      drag_ = drag;
    }
  }
  if (drag_) {
    std::string change;
    glm::dvec3 deltaM;
    double angleDeg, factor;
    const json::Json object = dragged(view, part, io.MousePos, snap, cellSizeM, change, deltaM, angleDeg, factor);
    // The outline where the drag takes the part: its bounds moved, turned about the middle, or scaled about it.
    if (part.boundsM) {
      const glm::dvec3 low = part.boundsM->first, high = part.boundsM->second;
      const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), glm::radians(angleDeg), unitAxis(drag_->axis % 3));
      const auto place = [&](const glm::dvec3& corner) {
        const glm::dvec3 fromAnchor = glm::dvec3(turn * glm::dvec4(factor * (corner - part.anchorM), 0.0));
        return view.project(part.anchorM + fromAnchor + deltaM);
      };
      for (int edge = 0; edge < 12; ++edge) {
        // Edge `edge` runs along axis edge / 4 from the corner whose other two coordinates are the edge's bits.
        const int along = edge / 4, bits = edge % 4;
        glm::dvec3 from, to;
        for (int i = 0, bit = 0; i < 3; ++i) {
          if (i == along) {
            from[i] = low[i];
            to[i] = high[i];
          } else {
            from[i] = to[i] = ((bits >> bit++) & 1) ? high[i] : low[i];
          }
        }
        const std::optional<ImVec2> a = place(from), b = place(to);
        if (a && b) draw->AddLine(*a, *b, kOutlineColour, 1.5f);
      }
    }
    draw->AddText(ImVec2(anchorPx_.x + 12, anchorPx_.y + 12), kOutlineColour, change.c_str());
    if (!io.MouseDown[0]) {
      if (object != part.object) edited = object;
      drag_.reset();
    }
  }

  const std::optional<int> hovered = drag_ ? std::optional<int>(drag_->axis) : hit(io.MousePos);
  for (int axis = 0; axis < 3; ++axis) {
    const ImU32 colour = hovered == axis ? kActiveColour : kAxisColours[axis];
    draw->AddLine(anchorPx_, tipsPx_[axis], colour, 3.0f);
    if (mode == HandleMode::Scale) {
      const ImVec2 tip = tipsPx_[axis];
      draw->AddRectFilled(ImVec2(tip.x - 4, tip.y - 4), ImVec2(tip.x + 4, tip.y + 4), colour);
    } else {
      draw->AddCircleFilled(tipsPx_[axis], mode == HandleMode::Turn ? 6.0f : 4.5f, colour);
    }
    const ImVec2 target(anchorPx_.x + 0.75f * (tipsPx_[axis].x - anchorPx_.x),
                        anchorPx_.y + 0.75f * (tipsPx_[axis].y - anchorPx_.y));
    targets_[std::string("#handle-") + kAxisNames[axis]] = target;
    if (planesDrawn_) {
      const ImU32 fill = hovered == axis + 3 ? kActiveColour : (kAxisColours[axis] & 0x00FFFFFFu) | 0x90000000u;
      draw->AddCircleFilled(planesPx_[axis], 6.0f, fill);
      targets_[std::string("#handle-") + kPlaneNames[axis]] = planesPx_[axis];
    }
  }
  return edited;
}

}  // namespace firn
