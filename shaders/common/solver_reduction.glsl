// The semi-implicit solve's status and dot products (common/solver.glsl; gpu_contract.h SolverStatus): the
// registers of each iteration's dot products, the dispatches of the iterations' passes, and the blocks' partial
// sums that solver_reduce.comp adds up.

layout(std430, binding = FIRN_BINDING_SOLVER_STATUS) coherent buffer SolverStatusBuffer {
  FIRN_MEMBERS(FIRN_SOLVER_STATUS)
  vec4 blockPartials[];  // per slot of the pool: the block's partial sum of this pass's dot product
};

// β_k = (z, A z)_k / (z, A z)_{k−1} of the conjugate residual method's direction p = z + β_k p (0 after a zero).
float conjugateResidualBeta(float productDot, uint k) {
  float previous = registers[k - 1u].x;
  return previous != 0.0 ? productDot / previous : 0.0;
}

// A block's partial sums: its nodes' values added in a fixed order (a tree over the work group), written to the
// block's slot for solver_reduce.comp. Every invocation of the group must call it.
shared vec4 blockSums[FIRN_BLOCK_GROUP_SIZE];
void writeBlockPartial(uint slot, vec4 nodeValues) {
  uint i = gl_LocalInvocationIndex;
  blockSums[i] = nodeValues;
  barrier();
  for (uint stride = uint(FIRN_BLOCK_GROUP_SIZE) / 2u; stride > 0u; stride /= 2u) {
    if (i < stride) blockSums[i] += blockSums[i + stride];
    barrier();
  }
  if (i == 0u) blockPartials[slot] = blockSums[0];
}

