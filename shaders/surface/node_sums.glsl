// What the nodes sum besides the volume fraction (SurfaceNodeSums per node): splat_density.comp adds to them,
// emit_mesh.comp and the caches divide them by it.
#include "surface/surface_contract.h"

layout(std430, binding = FIRN_BINDING_SURFACE_SUMS) buffer SurfaceNodeSumsBuffer { SurfaceNodeSums nodeSums[]; };
