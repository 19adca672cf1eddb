// The step's uniform block and the buffers every simulation pass reads, declared from the GPU contract
// (common/gpu_contract.h: binding points, structs and codes, shared with the host). Particle buffers live in
// particles.glsl (the renderer's vertex shader reads them too), grid buffers in grid.glsl.
#include "common/gpu_contract.h"

layout(std140, binding = FIRN_BINDING_STEP_UNIFORMS) uniform StepUniformsBlock { FIRN_MEMBERS(FIRN_STEP_UNIFORMS) };

#include "common/particles.glsl"

layout(std430, binding = FIRN_BINDING_MATERIALS) readonly buffer MaterialsBuffer { MaterialParams materials[]; };

#include "common/invocation.glsl"

// A node's linear index in the dense domain: how the watchdog names it (grid nodes are stored by block).
uint nodeIndex(ivec3 node) { return uint(node.x + gridNodes.x * (node.y + gridNodes.y * node.z)); }
vec3 nodePosition(ivec3 node) {
  precise vec3 positionM = gridOriginM + vec3(node) * cellSizeM;  // as the weights (common/bspline.glsl)
  return positionM;
}
