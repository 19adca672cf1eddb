#version 430 core
// The semi-implicit solve's search direction (common/solver.glsl): p = z + β_k p and A p = A z + β_k A p with
// β_k = (z, A z)_k / (z, A z)_{k−1} (p = z in the first two iterations: the first's z is v* − x₀, after which the
// method starts afresh), and the block's partial sum of (A p, P⁻¹ A p).
// A work group per active block, an invocation per node.
// Reads: the registers, the grid's masses, residual (its w: the preconditioner P), preconditioned, product,
// direction, directionProduct. Writes: direction, directionProduct, the block's partial sums.
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

uniform uint iteration;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

  SolverNode node = solverNodes[i];
  vec3 direction = node.preconditioned.xyz;
  vec3 directionProduct = node.product.xyz;
  // The first two iterations' directions are z itself: the first's is v* − x₀ (solver_residual.comp), not a
  // preconditioned residual, so the method starts afresh after it. What the vectors hold from before (another
  // step's values in a reused slot) is not multiplied by a zero, which would turn a stale infinity into NaN.
  if (iteration > 1u) {
    float previous = registers[iteration - 1u].x;
    float beta = previous != 0.0 ? registers[iteration].x / previous : 0.0;
    direction += beta * node.direction.xyz;
    directionProduct += beta * node.directionProduct.xyz;
  }
  solverNodes[i].direction.xyz = direction;
  solverNodes[i].directionProduct.xyz = directionProduct;
  float inverse = inversePreconditioner(storedFloats(gridMomentumMass[i]).w, node.residual.w);
  writeBlockPartial(slot, vec4(0.0, dot(directionProduct, directionProduct) * inverse, 0.0, 0.0));
}
