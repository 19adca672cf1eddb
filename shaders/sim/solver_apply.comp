#version 430 core
// The semi-implicit solve's product A z = S (M z + β Δt² H z) (common/solver.glsl), from the Hessian product's sums
// (solver_product.comp), and the block's partial sums of the iteration's dot products: x (r, P⁻¹ A z), which is the
// conjugate residual method's (z, A z) where z = P⁻¹ r and the first iteration's numerator, whose z is the direction
// v* − x₀ (solver_residual.comp); y (A z, P⁻¹ A z) and w (A z, P⁻¹ A p) with the last direction's product, from
// which solver_reduce.comp forms (A p, P⁻¹ A p) of this iteration's direction (solver_step.comp) without a pass of
// its own. A work group per active block, an invocation per node.
// Reads: solverStatus (the solveBlockDispatch record), blockTable (blockCounts, and slots[].block with rigid bodies),
//        gridMomentumMass (the masses),
//        solverNodes (the product sums and residual and preconditioned and directionProduct and constraint),
//        solverPreconditioner (the inverse), colliders (with rigid bodies: their centres).
// Writes: solverNodes (product with its held normal component in w and the product sums cleared),
//         solverStatus (the block's partial sums), bodies (with rigid bodies: their sums),
//         watchdog (a body's sum out of range).
// At a node a rigid body holds (common/solver_bodies.glsl), the held part of A z goes to the body's sums.
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"
#ifdef FIRN_HAS_RIGID_BODIES
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/solver_bodies.glsl"
#endif

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

uniform uint iteration;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

  float massKg = storedFloats(gridMomentumMass[i]).w;
  vec3 z = solverNodes[i].preconditioned.xyz;
  vec4 constraint = solverNodes[i].constraint;
  vec3 unprojected = massKg * z + takeProduct(i);
  vec3 product = constrain(unprojected, constraint);
  solverNodes[i].product = vec4(product, heldNormalComponent(unprojected, constraint));
#ifdef FIRN_HAS_RIGID_BODIES
  int body = constraintBody(constraint);
  if (body >= 0) {
    ivec3 node = nodeOfBlock(blockCoordinates(slots[slot].block), gl_LocalInvocationIndex);
    addToBodySums(body, fromBodyCentreCells(body, nodePosition(node)), unprojected - product, node);
  }
#endif
  vec3 residual = solverNodes[i].residual.xyz;
  vec3 scaledProduct = precondition(i, product);
  // The first two iterations' directions are z alone (solver_step.comp): the last direction's product is not read,
  // whatever a reused slot left there.
  float crossTerm = iteration > 1u ? dot(scaledProduct, solverNodes[i].directionProduct.xyz) : 0.0;
  writeBlockPartial(slot, vec4(dot(residual, scaledProduct), dot(product, scaledProduct), 0.0, crossTerm));
}
