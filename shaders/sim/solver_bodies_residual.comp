#version 430 core
// Rigid bodies in the semi-implicit solve (common/solver_bodies.glsl, eq. 39a): their start, after
// solver_residual.comp has summed the nodes they hold. A body starts at u₀ = u*, its velocities with gravity and the
// images' push (predict_bodies.comp), and the nodes it holds on its surface moving so (update_grid.comp), so its
// residual is r₀ = M_b (u* − u₀) − Σ Gᵀ P (A x₀ − M v*) = −(its sums: the grid update's response at those nodes and
// the start's Hessian product there). Its preconditioner is the body's diagonal block of eq. 39a,
// P_b = M_b + Σ Gᵀ P (m + β Δt² Hᵢᵢ) P G, inverted by Cholesky's factorization; the first iteration's direction
// leaves the body where it is (the nodes' is v* − x₀, whose held components are 0), and the partial sums of
// (r₀, P_b⁻¹ r₀) and of the tolerance's reference, (M_b u*, P_b⁻¹ M_b u*), go to the slots after the blocks'.
// One work group, an invocation per body.
// Reads: solverStatus (the solveReduceDispatch record), blockTable (blockCounts), colliders (the bodies' entries),
//        bodies (the mass and inertia, the sums and the block sums).
// Writes: bodies (velocity, w whether the body holds a node, and residual and preconditioned and direction and
//         directionProduct and inverse, the sums and block sums cleared), solverStatus (the bodies' partial sums).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"
#include "common/solver_bodies.glsl"

layout(local_size_x = FIRN_REDUCTION_GROUP_SIZE) in;

// Body b's block P_b from its block sums in P2G's nondimensional units (cleared) and its mass, inverted; whether it
// holds a node.
bool invertBodyBlock(int b) {
  float upper[21];
  float valuePerUnit = ldexp(1.0, -COUPLING_FRACTION_BITS);
  bool holds = false;
  for (int w = 0; w < 6; ++w) {
    holds = holds || nonzero(bodyRecords[b].blockLow[w], bodyRecords[b].blockHigh[w]);
    vec4 values = fixed64ToFloat(bodyRecords[b].blockLow[w], bodyRecords[b].blockHigh[w]) * valuePerUnit;
    for (int c = 0; c < 4 && 4 * w + c < 21; ++c) upper[4 * w + c] = values[c];
    bodyRecords[b].blockLow[w] = uvec4(0u);
    bodyRecords[b].blockHigh[w] = ivec4(0);
  }
  float massUnits = bodyRecords[b].massRadius.x * massUnitsPerKg;
  addBodyMass(massUnits, worldInertia(b) * (massUnitsPerKg * cellsPerM * cellsPerM), upper);
  storeBlockInverse(b, upper);
  return holds;
}

void main() {
  uint blocks = activeBlocks();
  for (uint k = gl_LocalInvocationIndex; k < rigidBodyCount; k += uint(FIRN_REDUCTION_GROUP_SIZE)) {
    int b = int(k);
    ColliderParams body = colliders[bodyEntry(b)];
    vec3 force, moment;
    takeBodySums(b, force, moment);
    bool holds = invertBodyBlock(b);
    bool takesPart = body.shapeBoundary.w != 0;  // a parked body holds no node and stays as it is
    vec3 residual0 = takesPart ? -force : vec3(0.0);
    vec3 residual1 = takesPart ? -moment : vec3(0.0);
    vec3 scaled0, scaled1;
    blockInverseTimes(b, residual0, residual1, scaled0, scaled1);
    vec3 momentum0, momentum1, scaledMomentum0, scaledMomentum1;
    bodyMassTimes(b, body.velocity.xyz, body.angularVelocity.xyz, momentum0, momentum1);
    blockInverseTimes(b, momentum0, momentum1, scaledMomentum0, scaledMomentum1);
    bodyRecords[b].velocity[0] = vec4(body.velocity.xyz, holds ? 1.0 : 0.0);
    bodyRecords[b].velocity[1] = vec4(body.angularVelocity.xyz, 0.0);
    bodyRecords[b].residual[0] = vec4(residual0, 0.0);
    bodyRecords[b].residual[1] = vec4(residual1, 0.0);
    for (int part = 0; part < 2; ++part) {
      bodyRecords[b].preconditioned[part] = vec4(0.0);
      bodyRecords[b].direction[part] = vec4(0.0);
      bodyRecords[b].directionProduct[part] = vec4(0.0);
    }
    float referenceDot = takesPart ? bodyDot(momentum0, momentum1, scaledMomentum0, scaledMomentum1) : 0.0;
    blockPartials[blocks + k] =
        vec4(0.0, 0.0, bodyDot(residual0, residual1, scaled0, scaled1), referenceDot);
  }
}
