#pragma once
// The scene editor's handles in the view (apps/firn/SceneEditor.h): three arrows along x, y and z from the selected
// part's middle and, for moving, a disc in each plane between two of them. Dragging an arrow moves the part along
// that axis (the point of the axis nearest the pointer's ray follows the pointer), a disc moves it in that plane
// (where the pointer's ray meets the plane), and in the other modes an arrow turns the part about the world's axis
// through its middle or scales it about its middle, by how far the pointer goes across the view. While a drag lasts the part's outline shows where it goes; its end
// is one edit of the part (scene/PartTransforms.h), snapped to whole cells, 15° or the cell's size when asked.
#include <map>
#include <optional>
#include <string>

#include <glm/vec3.hpp>
#include <imgui.h>

#include "render/Camera.h"
#include "render/Picking.h"
#include "scene/JsonChecker.h"

namespace firn {

// The window's view of the scene: its camera and where it lies in the window (pixels, y down).
struct ViewCamera {
  render::Camera camera;
  ImVec2 originPx;
  ImVec2 sizePx;

  float aspect() const { return sizePx.y > 0 ? sizePx.x / sizePx.y : 1.0f; }
  bool contains(const ImVec2& px) const;
  // Where a point appears in the window; nothing behind the camera.
  std::optional<ImVec2> project(const glm::dvec3& pointM) const;
  render::Ray ray(const ImVec2& px) const;
  // Metres per pixel at a point's depth.
  double metresPerPixel(const glm::dvec3& pointM) const;
};

enum class HandleMode { Move, Turn, Scale };

// The selected part as the handles need it: its object in the file, its section ("bodies", "colliders",
// "rigid_bodies"), the point the handles start from, and its bounds (none for a plane) to outline.
struct HandledPart {
  std::string pointer;
  std::string section;
  json::Json object;
  glm::dvec3 anchorM{0.0};
  std::optional<std::pair<glm::dvec3, glm::dvec3>> boundsM;
};

class PartHandles {
 public:
  // Draws the part's handles (and while a drag lasts, its outline where the drag takes it) over the view, and follows
  // the pointer. Returns the part's object as the drag leaves it when a drag ends with a change: one edit.
  std::optional<json::Json> update(const ViewCamera& view, const HandledPart& part, HandleMode mode, bool snap,
                                   double cellSizeM);
  // Whether a press at `px` (the window's pixels) falls on a handle as last drawn; one that does starts a drag.
  bool handleAt(const ImVec2& px) const;
  bool dragging() const { return drag_.has_value(); }
  void cancel() { drag_.reset(); }
  // The handles' centres as last drawn ("#handle-x", "#handle-xy", …), for scripted clicks.
  const std::map<std::string, ImVec2>& targets() const { return targets_; }

 private:
  struct Drag {
    int axis = 0;          // 0–2 along x, y, z; 3–5 in the planes yz, zx, xy (the plane's normal axis + 3)
    HandleMode mode = HandleMode::Move;
    ImVec2 pressPx;
    glm::dvec3 grabM{0.0};  // where the pointer took the axis or the plane
    std::string pointer;
  };
  // The part's object for the pointer at `px`, and what it changed, in words.
  json::Json dragged(const ViewCamera& view, const HandledPart& part, const ImVec2& px, bool snap, double cellSizeM,
                     std::string& change, glm::dvec3& deltaM, double& angleDeg, double& factor) const;
  std::optional<int> hit(const ImVec2& px) const;

  std::optional<Drag> drag_;
  // The handles as last drawn, in the window's pixels.
  ImVec2 anchorPx_;
  ImVec2 tipsPx_[3];
  ImVec2 planesPx_[3];
  bool drawn_ = false;
  bool planesDrawn_ = false;
  std::map<std::string, ImVec2> targets_;
};

}  // namespace firn
