#version 430 core
// Rigid bodies in the semi-implicit solve (common/solver_bodies.glsl, eq. 39a): a body's step of the iteration, as
// solver_step.comp takes a node's and before it, since the nodes a body holds take its new z_b: the direction
// p = z + β_k p and A p = A z + β_k A p, then u += α p, r −= α A p, z = P_b⁻¹ r, and the partial sum of (r, z).
// One work group, an invocation per body.
// Reads: solverStatus (the registers and the solveReduceDispatch record), blockTable (blockCounts),
//        bodies (velocity and residual and preconditioned and product and direction and directionProduct and
//        inverse).
// Writes: bodies (velocity and residual and preconditioned and direction and directionProduct),
//         solverStatus (the bodies' partial sums).
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
  vec4 dots = registers[iteration];  // x: (z, A z), y: (A p, P⁻¹ A p)
  float alpha = dots.y > 0.0 ? dots.x / dots.y : 0.0;
  float beta = iteration > 1u ? conjugateResidualBeta(dots.x, iteration) : 0.0;
  for (uint k = gl_LocalInvocationIndex; k < rigidBodyCount; k += uint(FIRN_REDUCTION_GROUP_SIZE)) {
    int b = int(k);
    vec3 residual[2];
    for (int part = 0; part < 2; ++part) {
      vec3 direction = bodyRecords[b].preconditioned[part].xyz;
      vec3 directionProduct = bodyRecords[b].product[part].xyz;
      if (iteration > 1u) {
        direction += beta * bodyRecords[b].direction[part].xyz;
        directionProduct += beta * bodyRecords[b].directionProduct[part].xyz;
      }
      bodyRecords[b].direction[part].xyz = direction;
      bodyRecords[b].directionProduct[part].xyz = directionProduct;
      bodyRecords[b].velocity[part].xyz += alpha * direction;
      residual[part] = bodyRecords[b].residual[part].xyz - alpha * directionProduct;
      bodyRecords[b].residual[part].xyz = residual[part];
    }
    vec3 scaled0, scaled1;
    blockInverseTimes(b, residual[0], residual[1], scaled0, scaled1);
    bodyRecords[b].preconditioned[0].xyz = scaled0;
    bodyRecords[b].preconditioned[1].xyz = scaled1;
    blockPartials[blocks + k] = vec4(0.0, 0.0, bodyDot(residual[0], residual[1], scaled0, scaled1), 0.0);
  }
}
