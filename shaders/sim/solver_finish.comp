#version 430 core
// The semi-implicit solve's end (common/solver.glsl): a node a collider held along its normal takes the collider's
// Coulomb friction now, bounded by the whole normal impulse of the step, the approach update_grid.comp removed and the
// push the held component took in the solve (SolverNode.residual.w; common/colliders.glsl). The solution keeps the
// components its constraints held at their collided values, but a node the constraints left free — outside the
// colliders, or separating from one, when v* was computed — may now move into a collider or out of the domain: it meets
// them as update_grid.comp's nodes do. A node the solve did not change meets them unchanged, so with β = 0 the step is
// the explicit one to the bit (for colliders at rest: the friction's relative velocity is v − v_c). A work group per
// active block, an invocation per node. With rigid bodies, each body whose solid holds a node with another collider or
// a wall takes its part of the constraints' push in the solve (eq. 35a, from the product of the solution:
// common/colliders.glsl, constraintsAfterSolve; at a node it alone holds, its push is its own in the solve, eq. 39a),
// and of the friction; with moving colliders, their part of that push, the friction and the collisions are their work
// on the snow, for the energy audit (common/energy.glsl).
// Reads: blockTable (blockCounts and slots[].block and .auditedElsewhere and the blockDispatch record),
//        gridMomentumMass (the velocities and masses),
//        solverNodes (constraint and residual.w: the colliders' normal impulses and FIRN_SOLUTION_PRODUCT's sums),
//        colliders, watchdog (the ledger's and the loads' atomics' old values).
// Writes: gridMomentumMass (the velocities),
//         solverNodes (FIRN_SOLUTION_PRODUCT with rigid bodies or moving colliders: the product sums cleared),
//         colliders (rigid bodies: their sums), watchdog (the energy ledger's flows and the objects' loads).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/solver.glsl"
#include "common/energy.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  ivec3 node = nodeOfBlock(blockCoordinates(slots[slot].block), gl_LocalInvocationIndex);
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

#ifdef FIRN_SOLUTION_PRODUCT
  // β Δt² H x, the product of the solution (ImplicitSolver: a product after the solve where the scene has rigid
  // bodies or moving colliders), taken at every node so that no sums carry into the next step's.
  vec3 product = takeProduct(i);
#endif
  vec4 velocityMass = storedFloats(gridMomentumMass[i]);
  if (velocityMass.w <= 0.0) return;
  countedHere = slots[slot].auditedElsewhere == 0u;  // another process holding the node counts it
  int code = int(solverNodes[i].constraint.w);
  vec3 x = nodePosition(node);
  vec3 velocity = velocityMass.xyz;
  float workJ = 0.0;
#ifdef FIRN_SOLUTION_PRODUCT
  // Its held components are the constraints' push on the snow, whose opposite the bodies take.
  // A node a body's unknowns held pushed it within the solve (solver_bodies_finish.comp).
  if (constraintBody(solverNodes[i].constraint) < 0) {
    constraintsAfterSolve(x, timeS, solverNodes[i].constraint, product - constrain(product, solverNodes[i].constraint),
                          workJ);
  }
#endif
  if ((code & (CONSTRAINT_NORMAL | CONSTRAINT_FIXED)) == 0) {
    velocity = collideWithColliders(x, velocity, timeS, velocityMass.w, workJ);
  } else {
    velocity = collidersFrictionAfterSolve(x, velocity, timeS, velocityMass.w, solverNodes[i].constraint,
                                           solverNodes[i].residual.w, workJ);
  }
  velocity = collideWithDomainWalls(x, velocity, interiorMin(), interiorMax());
  gridMomentumMass[i] = floatsToStored(vec4(velocity, velocityMass.w));
  addEnergyFlows(vec4(workJ, 0.0, 0.0, 0.0));
}
