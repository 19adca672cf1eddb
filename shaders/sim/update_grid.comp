#version 430 core
// Grid update: a work group per active block (striding over them: common/blocks.glsl, FIRN_STRIDE_OVER_BLOCKS), an
// invocation per node of it.
// v_i* = (Σ w m v)_i / m_i + Δt (f_i / m_i + g) (Stomakhin 2013 eq. 9–10, explicit), then colliders and the domain
// walls. Nodes without mass stay zero. A semi-implicit step meets the colliders without friction here and takes it
// after the solve (common/colliders.glsl, collideForSolve).
// With rigid bodies (explicit step), the bodies wait for their coupled solve: this pass adds the nodes they hold to
// their sums (common/body_blocks.glsl, addToCoupling) and couple_nodes.comp meets them after solve_coupling.comp.
// In the semi-implicit step a node that one body alone holds becomes one of that body's unknowns in the solve
// (common/solver_bodies.glsl): the node starts on the body's surface, and the body's sums take its response.
// The energy ledger's flows take the moving colliders' work (common/energy.glsl). What the walls take here stays in
// the dissipated energy, as a collider at rest's does: a wall stops, each step, the velocity the step's forces gave
// the nodes pressed into it, which had moved nothing, and that cancels only against the step's own truncation.
// Reads: blockTable (blockCounts and slots[].block and .auditedElsewhere and the blockDispatch record),
//        gridMomentumMass (the momentum and mass sums), gridImpulse (PIC/FLIP or semi-implicit: the impulse sums),
//        colliders (with colliders or rigid bodies), watchdog (the ledger's and the loads' atomics' old values).
// Writes: gridMomentumMass (the same storage as floats: velocity m/s and mass kg),
//         gridImpulse (PIC/FLIP: the velocity before forces),
//         solverNodes (semi-implicit steps: the node's constraint and residual.w and the solve's start in direction),
//         bodies (rigid bodies: the sums of the nodes a body alone holds, and the explicit step's coupling sums),
//         colliders (rigid bodies: the snow's push),
//         watchdog (the energy ledger's flows: the moving colliders' work and the objects' loads).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#ifdef FIRN_HAS_RIGID_BODIES
// The bodies' records (the explicit step's coupling sums, the semi-implicit solve's unknowns), first here: the shader
// library includes a file once, where it first appears, and the semi-implicit branch below includes it too.
#include "common/body_blocks.glsl"
#endif
#ifdef FIRN_SEMI_IMPLICIT
#include "common/solver.glsl"
#ifdef FIRN_HAS_RIGID_BODIES
#include "common/solver_bodies.glsl"
#endif
#endif
#include "common/energy.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void updateNode(uint slot) {
  ivec3 node = nodeOfBlock(blockCoordinates(slots[slot].block), gl_LocalInvocationIndex);
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

  vec4 sums = storedToNondimensional(gridMomentumMass[i]);
  vec3 velocity = vec3(0.0);
  vec3 velocityBeforeForces = vec3(0.0);
  float massKg = 0.0;
#ifdef FIRN_SEMI_IMPLICIT
  vec4 constraint = vec4(0.0, 0.0, 0.0, float(CONSTRAINT_FIXED));  // a node without mass stays at rest
  float approachMPerS = 0.0;
#endif
  // A node that another process holds too is counted there (docs/distributed.md).
  countedHere = slots[slot].auditedElsewhere == 0u;
  if (sums.w > 0.0) {
    massKg = sums.w * referenceMassKg;
    float unitsToVelocity = momentumUnitKgMPerS / massKg;
#ifdef FIRN_GRID_IMPULSE
    vec3 impulse = storedToNondimensional(gridImpulse[i]).xyz;
    velocityBeforeForces = sums.xyz * unitsToVelocity;
    velocity = (sums.xyz + impulse) * unitsToVelocity + dtS * gravityMPerS2;
#else
    velocity = sums.xyz * unitsToVelocity + dtS * gravityMPerS2;  // impulse already in the momentum
#endif
    vec3 x = nodePosition(node);
    float workJ = 0.0;
#ifdef FIRN_SEMI_IMPLICIT
    int soleBody;
    vec3 soleBodyImpulseKgMPerS;
    constraint = collideForSolve(x, velocity, timeS, massKg, approachMPerS, workJ, soleBody, soleBodyImpulseKgMPerS);
#elif defined(FIRN_HAS_RIGID_BODIES)
    // The scene's colliders and the walls now; the bodies after their coupled solve (eq. 39): this node's share of
    // each body's sums, and couple_nodes.comp gives it the motion solved.
    uint firstBody = colliderCount - rigidBodyCount;
    velocity = collideWithEntries(0u, firstBody, x, velocity, timeS, massKg, workJ);
    velocity = collideWithDomainWalls(x, velocity, interiorMin(), interiorMax());
    for (uint b = firstBody; b < colliderCount; ++b) {
      if (colliderWithinReach(b, x, timeS)) addToCoupling(b, x, timeS, massKg, velocity);
    }
#else
    velocity = collideWithColliders(x, velocity, timeS, massKg, workJ);
#endif
#ifdef FIRN_SEMI_IMPLICIT
    int walls = wallConstraint(x, velocity, interiorMin(), interiorMax());
    // A normal and a wall's axis together: held whole, so that the projection stays one.
    if (walls != 0 && (int(constraint.w) & CONSTRAINT_NORMAL) != 0) constraint.w = float(CONSTRAINT_FIXED);
    constraint.w = float(int(constraint.w) | walls);
#ifdef FIRN_HAS_RIGID_BODIES
    // A node a body alone holds is one of its unknowns in the solve (common/solver_bodies.glsl): its response's
    // impulse starts the body's residual, and the solve gives the body what the node takes. With a wall's axis
    // held too it stays a constraint of the body's velocities now, which take the push.
    if (soleBody >= 0 && walls == 0) {
      constraint.w = float(int(constraint.w) | ((soleBody + 1) << CONSTRAINT_BODY_SHIFT));
      addToBodySums(soleBody, fromBodyCentreCells(soleBody, x), soleBodyImpulseKgMPerS, node);
    } else if (soleBody >= 0) {
      pushBodyAtNode(soleBody, x, timeS, soleBodyImpulseKgMPerS);
    }
#endif
#endif
    velocity = collideWithDomainWalls(x, velocity, interiorMin(), interiorMax());
    addEnergyFlows(vec4(workJ, 0.0, 0.0, 0.0));
  }
#ifdef FIRN_SEMI_IMPLICIT
  solverNodes[i].constraint = constraint;
  solverNodes[i].residual.w = approachMPerS;  // the collider's normal impulse / m so far (solver_finish.comp)
  // The solve's start x₀, for the initial residual's product (solver_residual.comp): the velocity before the elastic
  // force, with gravity, and with the held components' values of v*. A start at v* = x₀ + Δt M⁻¹ f has the residual
  // β Δt² H Δt M⁻¹ f more, and H multiplies the force's roughest modes by up to (c Δt / h)², the square of the step
  // over its elastic bound; where the force is smooth and balanced (snow at rest) v* is the better start. The first
  // iteration takes the step along v* − x₀ that leaves the least residual (docs/numerics.md), so the solve starts
  // from the better of the two, or a blend. With β = 0, v* is the solution and the start.
  vec3 start = velocity;
  if (implicitRatio > 0.0) start += constrain(velocityBeforeForces + dtS * gravityMPerS2 - velocity, constraint);
  solverNodes[i].direction.xyz = start;
#endif
  gridMomentumMass[i] = floatsToStored(vec4(velocity, massKg));
#ifndef FIRN_TRANSFER_APIC
  gridImpulse[i] = floatsToStored(vec4(velocityBeforeForces, 0.0));
#endif
}

void main() {
#ifdef FIRN_STRIDE_OVER_BLOCKS
  for (uint slot = workGroupSlot(); slot < activeBlocks(); slot += workGroupCount()) updateNode(slot);
#else
  uint slot = workGroupSlot();
  if (slot < activeBlocks()) updateNode(slot);
#endif
}
