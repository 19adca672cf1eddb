#version 430 core
// The semi-implicit solve's start, once per step (common/solver.glsl): the iterations' passes are dispatched over
// this step's blocks and tiles, and the registers of last step's dot products and the least rounding stiffness are
// cleared.
// Reads: blockTable (blockDispatch and tileDispatch).
// Writes: solverStatus (registers and the dispatch records and solveEnd and roundingStiffness).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"

layout(local_size_x = FIRN_REDUCTION_GROUP_SIZE) in;

void main() {
  for (uint k = gl_LocalInvocationIndex; k < uint(SOLVER_REGISTERS); k += uint(FIRN_REDUCTION_GROUP_SIZE)) {
    registers[k] = vec4(0.0);
  }
  if (gl_LocalInvocationIndex == 0u) {
    solveBlockDispatch = blockDispatch;
    solveProductDispatch = tileDispatch;
    solveReduceDispatch = uvec4(1u, 1u, 1u, 0u);
    solveEnd = uvec4(0u);
    roundingStiffness = uvec4(0x7f800000u, 0u, 0u, 0u);  // +∞
  }
}
