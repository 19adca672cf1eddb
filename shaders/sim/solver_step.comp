#version 430 core
// The semi-implicit solve's step (common/solver.glsl): the search direction p = z + β_k p and its product
// A p = A z + β_k A p, with β_k = (z, A z)_k / (z, A z)_{k−1}; then the step along it, α = (z, A z)_k / (A p, P⁻¹ A p)_k,
// x += α p (the grid's velocities), r −= α A p, z = P⁻¹ r, and the block's partial sum of (r, z), the residual after
// the iteration. The dot products come from one reduction of solver_apply.comp's partial sums (solver_reduce.comp
// forms (A p, P⁻¹ A p) from them), so an iteration takes one node pass fewer than the method's textbook form.
// In the first iteration p = z is v* − x₀ (solver_residual.comp) and (z, A z) is (r, P⁻¹ A z), so α is the step that
// leaves the least residual on that line; the second starts the method afresh (p = z). What the vectors hold from
// before (another step's values in a reused slot) is then never multiplied by a zero, which would turn a stale
// infinity into NaN.
// A work group per active block, an invocation per node.
// Reads: solverStatus (the registers and the solveBlockDispatch record),
//        blockTable (blockCounts, and slots[].block with rigid bodies), gridMomentumMass (the velocities and masses),
//        solverNodes (residual and preconditioned and product and direction and directionProduct),
//        solverPreconditioner (the inverse), colliders (with rigid bodies: their centres),
//        bodies (with rigid bodies: preconditioned).
// Writes: gridMomentumMass (the velocities: x), solverStatus (the block's partial sums),
//         solverNodes (residual with w: the normal impulse and preconditioned and direction and directionProduct).
// At a node a rigid body holds (common/solver_bodies.glsl), z's held components are the body's surface moving at its
// new z_b (solver_bodies_step.comp runs first), P G z_b, so that every vector of the grid is T of the unknowns'.
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

  vec4 dots = registers[iteration];  // x: (z, A z), y: (A p, P⁻¹ A p)
  vec3 direction = solverNodes[i].preconditioned.xyz;
  vec4 directionProduct = solverNodes[i].product;  // w: its held normal component
  if (iteration > 1u) {
    float beta = conjugateResidualBeta(dots.x, iteration);
    direction += beta * solverNodes[i].direction.xyz;
    directionProduct += beta * solverNodes[i].directionProduct;
  }
  float alpha = dots.y > 0.0 ? dots.x / dots.y : 0.0;
  vec4 velocityMass = storedFloats(gridMomentumMass[i]);
  gridMomentumMass[i] = floatsToStored(vec4(velocityMass.xyz + alpha * direction, velocityMass.w));
  vec3 residual = solverNodes[i].residual.xyz - alpha * directionProduct.xyz;
  vec3 preconditioned = precondition(i, residual);
  solverNodes[i].direction.xyz = direction;
  solverNodes[i].directionProduct = directionProduct;
  solverNodes[i].residual.xyz = residual;
  // x moves by α p, so the held component's push n·(A x − M v*) by α n·(A p): the collider's normal impulse.
  if (velocityMass.w > 0.0) solverNodes[i].residual.w += alpha * directionProduct.w / velocityMass.w;
  vec3 heldMotion = vec3(0.0);
#ifdef FIRN_HAS_RIGID_BODIES
  int body = constraintBody(solverNodes[i].constraint);
  if (body >= 0) {
    vec3 x = nodePosition(nodeOfBlock(blockCoordinates(slots[slot].block), gl_LocalInvocationIndex));
    heldMotion = heldBodyMotion(body, x, bodyRecords[body].preconditioned[0].xyz,
                                bodyRecords[body].preconditioned[1].xyz, solverNodes[i].constraint);
  }
#endif
  solverNodes[i].preconditioned.xyz = preconditioned + heldMotion;
  writeBlockPartial(slot, vec4(0.0, 0.0, dot(residual, preconditioned), 0.0));
}
