#version 430 core
// Rigid bodies in the semi-implicit solve (common/solver_bodies.glsl, eq. 39a): a body's rows of the product A z,
// after solver_apply.comp has summed the held parts of the nodes' products, (A z)_b = Σ Gᵀ P (A T z) + M_b z_b, and
// its partial sums of the iteration's dot products, as solver_apply.comp forms a block's: x (r, P⁻¹ A z),
// y (A z, P⁻¹ A z), w (A z, P⁻¹ A p) with the last direction's product, in the slots after the blocks'.
// One work group, an invocation per body.
// Reads: solverStatus (the solveReduceDispatch record), blockTable (blockCounts), colliders (the bodies' entries),
//        bodies (the mass and inertia, the sums and residual and preconditioned and directionProduct and inverse).
// Writes: bodies (product, the sums cleared), solverStatus (the bodies' partial sums).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"
#include "common/solver_bodies.glsl"

layout(local_size_x = FIRN_REDUCTION_GROUP_SIZE) in;

uniform uint iteration;

void main() {
  uint blocks = activeBlocks();
  for (uint k = gl_LocalInvocationIndex; k < rigidBodyCount; k += uint(FIRN_REDUCTION_GROUP_SIZE)) {
    int b = int(k);
    vec3 product0, product1, mass0, mass1;
    takeBodySums(b, product0, product1);
    bodyMassTimes(b, bodyRecords[b].preconditioned[0].xyz, bodyRecords[b].preconditioned[1].xyz, mass0, mass1);
    product0 += mass0;
    product1 += mass1;
    bodyRecords[b].product[0] = vec4(product0, 0.0);
    bodyRecords[b].product[1] = vec4(product1, 0.0);
    vec3 scaled0, scaled1;
    blockInverseTimes(b, product0, product1, scaled0, scaled1);
    float crossTerm = iteration > 1u ? bodyDot(scaled0, scaled1, bodyRecords[b].directionProduct[0].xyz,
                                               bodyRecords[b].directionProduct[1].xyz)
                                     : 0.0;
    blockPartials[blocks + k] =
        vec4(bodyDot(bodyRecords[b].residual[0].xyz, bodyRecords[b].residual[1].xyz, scaled0, scaled1),
             bodyDot(product0, product1, scaled0, scaled1), 0.0, crossTerm);
  }
}
