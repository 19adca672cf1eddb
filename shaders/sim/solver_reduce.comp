#version 430 core
// The semi-implicit solve's dot products (common/solver.glsl): one work group sums the blocks' partial sums of the
// components `reduceComponents` marks into register `reduceRegister` (and for the iteration's products, forms the
// direction's norm from them: below). The sum is exact and so independent of the
// order of the slots: each partial becomes a 64-bit integer at the scale that puts the largest below 2^41 (room for
// 2^21 blocks), and integers add exactly. After the residual's sum it decides whether another iteration is needed,
// and if not empties the dispatches of the iterations the host has still to look at.
// Reads: solverStatus (blockPartials and registers and the solveReduceDispatch record),
//        blockTable (blockCounts and blockDispatch and tileDispatch).
// Writes: solverStatus (registers and the solver's dispatch records and solveEnd).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"

layout(local_size_x = FIRN_REDUCTION_GROUP_SIZE) in;

uniform uint reduceRegister;
uniform uint reduceComponents;  // bits 0–3: whether the components x, y, z, w are this pass's

const uint GROUP = uint(FIRN_REDUCTION_GROUP_SIZE);
const uint FLOAT_INFINITY_BITS = 0x7f800000u;

shared uvec4 largestBits[FIRN_REDUCTION_GROUP_SIZE];
shared uvec4 sumLow[FIRN_REDUCTION_GROUP_SIZE];
shared ivec4 sumHigh[FIRN_REDUCTION_GROUP_SIZE];

void main() {
  uint l = gl_LocalInvocationIndex;
  // The blocks' slots, then the rigid bodies' (solver_bodies_*.comp; none without bodies).
  uint blocks = activeBlocks() + rigidBodyCount;

  // The largest magnitude of each component: non-negative floats order as their bits do (NaN above infinity).
  uvec4 bits = uvec4(0u);
  for (uint s = l; s < blocks; s += GROUP) bits = max(bits, floatBitsToUint(abs(blockPartials[s])));
  largestBits[l] = bits;
  barrier();
  for (uint stride = GROUP / 2u; stride > 0u; stride /= 2u) {
    if (l < stride) largestBits[l] = max(largestBits[l], largestBits[l + stride]);
    barrier();
  }
  uvec4 largest = largestBits[0];
  // 2^scale puts the largest in [2^40, 2^41); held within ±100 so that ldexp never forms an infinite power.
  ivec4 scale = clamp(40 - (ivec4(largest >> 23u) - 127), ivec4(-100), ivec4(100));

  uvec4 low = uvec4(0u);
  ivec4 high = ivec4(0);
  for (uint s = l; s < blocks; s += GROUP) {
    vec4 scaled = floor(ldexp(blockPartials[s], scale) + 0.5);
    uvec4 addLow;
    ivec4 addHigh;
    splitFixed64(mix(scaled, vec4(0.0), greaterThanEqual(largest, uvec4(FLOAT_INFINITY_BITS))), addLow, addHigh);
    addFixed64(low, high, addLow, addHigh);
  }
  sumLow[l] = low;
  sumHigh[l] = high;
  barrier();
  for (uint stride = GROUP / 2u; stride > 0u; stride /= 2u) {
    if (l < stride) {
      uvec4 total = sumLow[l];
      ivec4 totalHigh = sumHigh[l];
      addFixed64(total, totalHigh, sumLow[l + stride], sumHigh[l + stride]);
      sumLow[l] = total;
      sumHigh[l] = totalHigh;
    }
    barrier();
  }
  if (l != 0u) return;

  vec4 total = ldexp(fixed64ToFloat(sumLow[0], sumHigh[0]), -scale);
  total = mix(total, vec4(uintBitsToFloat(0x7fc00000u)), greaterThanEqual(largest, uvec4(FLOAT_INFINITY_BITS)));
  bvec4 components = notEqual(uvec4(reduceComponents) & uvec4(1u, 2u, 4u, 8u), uvec4(0u));
  // The reference's sum comes with the rounding floor's in x (solver_residual.comp): the tolerance is met at
  // ‖r‖ ≤ max(tolerance ‖M v*‖, ‖δb‖), so the reference is the larger of (M v*, (M + β Δt² Hᵢᵢ)⁻¹ M v*) and
  // ‖δb‖² / tolerance².
  if (components.w) total.w = max(total.w, total.x / solverToleranceSquared);
  // The iteration's (A p, P⁻¹ A p) of p = z + β p' (solver_step.comp) from solver_apply.comp's sums: (A z, P⁻¹ A z)
  // + 2β (A z, P⁻¹ A p') + β² (A p', P⁻¹ A p'), the last the previous iteration's y. Each term is summed exactly,
  // and the first two iterations' directions are z alone.
  if (components.y && reduceRegister > 1u) {
    float beta = conjugateResidualBeta(total.x, reduceRegister);
    total.y = max(total.y + beta * (2.0 * total.w + beta * registers[reduceRegister - 1u].y), 0.0);
  }
  registers[reduceRegister] = mix(registers[reduceRegister], total, components);
  if (components.z) {
    // Another iteration while (r, P⁻¹ r) > tolerance² × the reference; a NaN residual ends the solve for the host to report.
    float reference = components.w ? total.w : registers[0].w;
    bool another = total.z > solverToleranceSquared * reference;
    solveBlockDispatch = another ? blockDispatch : uvec4(0u, 1u, 1u, 0u);
    solveProductDispatch = another ? tileDispatch : uvec4(0u, 1u, 1u, 0u);
    solveReduceDispatch = uvec4(another ? 1u : 0u, 1u, 1u, 0u);
    // The register the solve ended at, for the host to read: the GPU's float comparison is the one that counts.
    if (!another) solveEnd = uvec4(reduceRegister + 1u, 0u, 0u, 0u);
  }
}
