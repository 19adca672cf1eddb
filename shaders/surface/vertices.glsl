// The mesh's vertices (SurfaceVertex per vertex), which emit_mesh.comp writes and the renderer draws from.
#include "surface/surface_contract.h"

layout(std430, binding = FIRN_BINDING_SURFACE_VERTICES) buffer SurfaceVertexBuffer { SurfaceVertex vertices[]; };
