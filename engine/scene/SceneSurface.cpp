// The scene file's "surface" section (docs/scene-format.md, surface): how the snow's surface is reconstructed
// for `--render surface`, `--mesh` and `--vdb` (docs/surfaces.md).
#include "scene/SceneSections.h"

namespace firn::scenefile {

using json::Interval;

SurfaceSpec readSurface(const json::Object& surface) {
  surface.checkKeys({"resolution", "smoothing", "iso"}, "\"surface\"");
  SurfaceSpec spec;
  // Coarser than the simulation's cells loses what it resolves; beyond 8 the grid holds 512 nodes per cell.
  spec.resolution = surface.number("resolution", spec.resolution, Interval::closed(1, 8));
  // Below two spacings the kernels of a resting body's jittered lattice leave holes inside it (1.5 does,
  // docs/surfaces.md); beyond six they melt every feature of a body a dozen particles across.
  spec.smoothing = surface.number("smoothing", spec.smoothing, Interval::closed(2, 6));
  // A volume fraction: 0 would enclose all space, 1 only snow compacted past its rest density.
  spec.iso = surface.number("iso", spec.iso, Interval{0, 1, false, false});
  return spec;
}

}  // namespace firn::scenefile
