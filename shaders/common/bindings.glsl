// Buffers and the step's uniform block, mirroring engine/sim/GpuLayout.h. Binding points come from the
// host as FIRN_BINDING_* defines, so they are written once. Particle buffers live in particles.glsl (the
// renderer's vertex shader reads them too), grid buffers in grid.glsl.

layout(std140, binding = FIRN_BINDING_STEP_UNIFORMS) uniform StepUniforms {
  vec4 gridOriginCellSize;  // origin (m), h (m)
  ivec4 gridNodes;          // nodes per axis
  vec4 gravityDt;           // g (m/s²), Δt of this step (s)
  vec4 fixedPoint;          // m_ref (kg), momentum unit m_ref·h/Δt_ref (kg·m/s), 2^k, 2^-k
  vec4 transfer;            // FLIP ratio α, time at the start of the step (s), APIC D⁻¹ (1/m²)
  uvec4 counts;             // particles, colliders, step index
};

#include "common/particles.glsl"

struct MaterialParams {
  vec4 elastic;  // μ0 (Pa), λ0 (Pa), snow hardening ξ, density (kg/m³)
  vec4 plastic;  // snow: 1 − θc, 1 + θs; sand: h0, h1 (rad), h2, h3 (rad)
  vec4 fluid;    // water: bulk modulus k (Pa), γ, viscosity (Pa·s)
  ivec4 model;   // x: MODEL_* (materials.glsl)
};
layout(std430, binding = FIRN_BINDING_MATERIALS) readonly buffer MaterialBuffer { MaterialParams materials[]; };

struct ActiveRegionData {
  ivec4 particleCellMin;
  ivec4 particleCellMax;
  ivec4 boxMin;
  ivec4 boxSize;  // w: node count
  uvec4 gridDispatch;
  ivec4 addedCellMin;  // particles added since the last step (written by the host)
  ivec4 addedCellMax;
};
layout(std430, binding = FIRN_BINDING_ACTIVE_REGION) coherent buffer ActiveRegionBuffer { ActiveRegionData region; };

float cellSize() { return gridOriginCellSize.w; }
vec3 gridOrigin() { return gridOriginCellSize.xyz; }
float stepDt() { return gravityDt.w; }
uint particleCount() { return counts.x; }
uint stepIndex() { return counts.z; }

// Particle passes may be dispatched as a 2-D grid of work groups when there are more than 65,535 groups.
uint particleInvocationIndex() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(FIRN_PARTICLE_GROUP_SIZE);
}

uint nodeIndex(ivec3 node) { return uint(node.x + gridNodes.x * (node.y + gridNodes.y * node.z)); }
ivec3 nodeCoordinates(uint index) {
  int i = int(index);
  return ivec3(i % gridNodes.x, (i / gridNodes.x) % gridNodes.y, i / (gridNodes.x * gridNodes.y));
}
vec3 nodePosition(ivec3 node) { return gridOrigin() + vec3(node) * cellSize(); }
