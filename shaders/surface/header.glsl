// The reconstruction's header buffer (SurfaceHeader): the box of lattice nodes the particles' kernels reach.
#include "surface/surface_contract.h"

layout(std430, binding = FIRN_BINDING_SURFACE_HEADER) buffer SurfaceHeaderBuffer { FIRN_MEMBERS(FIRN_SURFACE_HEADER) };
