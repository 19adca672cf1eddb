#version 430 core
// After the semi-implicit solve, where the scene has rigid bodies or moving colliders: the solution x, held components
// and all, into z, for one more Hessian product (common/solver_product.glsl) whose held components at the nodes the
// colliders hold are the constraints' push on the snow, which the moving colliders do work with and a rigid body takes
// back where it holds a node with another collider or a wall (at the nodes it alone holds it is an unknown of the
// solve: solver_finish.comp; docs/algorithm.md, Rigid bodies; docs/numerics.md, The energy audit). A work group per
// active block, an invocation per node.
// Reads: blockTable (blockCounts and the blockDispatch record), gridMomentumMass (the velocities: the solution x).
// Writes: solverNodes (preconditioned).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;
  solverNodes[i].preconditioned.xyz = storedFloats(gridMomentumMass[i]).xyz;
}
