// The semi-implicit solve's storage and arithmetic (docs/numerics.md, "The semi-implicit solve").
//
// Stomakhin et al. 2013 eq. 9 takes the grid velocities of the step from (I + β Δt² M⁻¹ H) v = v*, H = ∂²Φ/∂x² the
// Hessian of the elastic energy and v* the explicit update (update_grid.comp). Firn solves the same system in its
// symmetric form A v = M v*, A = M + β Δt² H, by the conjugate residual method preconditioned with M⁻¹ (which is
// the method in the inner product of M⁻¹ A that eq. 9 suggests), with the colliders and walls as constraints: the
// projection S of each node's held components (SolverNode.constraint) is applied to every residual and product, so
// the held components keep the collided values of v*.
//
// Determinism. A Hessian product is summed at the nodes from every particle's contribution, like P2G. Its
// contributions are (c Δt / h)² times larger than the product they add up to, too many bits for P2G's 32-bit fixed
// point and lost in float sums, whose order would not repeat either. They are summed as 64-bit integers instead,
// two 32-bit words with the carry: exact, so the same whatever the order. A dot product is summed within a block in
// a fixed order, and over the blocks, whose slots follow no fixed order, as 64-bit integers at a scale set by the
// largest block's partial sum: again exact. A run repeats to the bit.
#include "common/watchdog.glsl"

//
// This file declares the nodes' vectors; common/solver_reduction.glsl the status and the dot products' sums. A
// compute shader may declare 16 storage blocks on llvmpipe, which counts every block declared, used or not
// (docs/platform.md), so the passes include what they use.

layout(std430, binding = FIRN_BINDING_SOLVER_NODES) coherent buffer SolverNodeBuffer { SolverNode solverNodes[]; };

float implicitRatio() { return solver.x; }
float toleranceSquared() { return solver.y; }

// --- 64-bit integers as a low (unsigned) and a high (signed) word -------------------------------------------------

const float TWO_TO_32 = 4294967296.0;
// Largest magnitude a value may have to fit 64 bits with room for a few additions: 2^62.
const float FIXED64_LIMIT = 4611686018427387904.0;

// x as (low, high): x is an integer-valued float below 2^62 in magnitude, so x − high·2^32 is exact.
void splitFixed64(vec4 x, out uvec4 low, out ivec4 high) {
  vec4 highPart = floor(x * (1.0 / TWO_TO_32));
  low = uvec4(x - highPart * TWO_TO_32);
  high = ivec4(highPart);
}

// (low, high) += (addLow, addHigh).
void addFixed64(inout uvec3 low, inout ivec3 high, uvec3 addLow, ivec3 addHigh) {
  uvec3 carry;
  low = uaddCarry(low, addLow, carry);
  high += addHigh + ivec3(carry);
}
void addFixed64(inout uvec4 low, inout ivec4 high, uvec4 addLow, ivec4 addHigh) {
  uvec4 carry;
  low = uaddCarry(low, addLow, carry);
  high += addHigh + ivec4(carry);
}

// The value of (low, high) as a float: its magnitude is converted, so that a small negative value (high −1, low
// near 2^32) does not cancel to nothing.
float fixed64ToFloat(uint low, int high) {
  bool negative = high < 0;
  uint carry;
  uint magnitudeLow = negative ? uaddCarry(~low, 1u, carry) : low;
  uint magnitudeHigh = negative ? uint(~high) + carry : uint(high);
  float magnitude = float(magnitudeHigh) * TWO_TO_32 + float(magnitudeLow);
  return negative ? -magnitude : magnitude;
}
vec4 fixed64ToFloat(uvec4 low, ivec4 high) {
  return vec4(fixed64ToFloat(low.x, high.x), fixed64ToFloat(low.y, high.y), fixed64ToFloat(low.z, high.z),
              fixed64ToFloat(low.w, high.w));
}

// --- Hessian products at the nodes -------------------------------------------------------------------------------

// A contribution in momentum units, as the 64-bit integer of units 2^−k_H; one too large (or NaN) is dropped and
// reported: k_H leaves 2^8 of headroom over the stiffest wave the scene states (sim/FixedPoint.h).
bool productToFixed64(vec3 momentumUnits, out uvec3 low, out ivec3 high) {
  vec3 scaled = floor(momentumUnits * solver.z + 0.5);
  bool fits = all(lessThan(abs(scaled), vec3(FIXED64_LIMIT)));  // also false for NaN
  uvec4 low4;
  ivec4 high4;
  splitFixed64(vec4(fits ? scaled : vec3(0.0), 0.0), low4, high4);
  low = low4.xyz;
  high = high4.xyz;
  return fits;
}

// Adds a node's sums, a word at a time: the low word's atomicAdd returns the sum before, which tells whether it
// carried into the high word. The words end as the exact 64-bit sum whatever the order of the additions.
void addProductToNode(uint address, uvec3 low, ivec3 high) {
  for (int c = 0; c < 3; ++c) {
    if (low[c] == 0u && high[c] == 0) continue;
    uint previous = atomicAdd(solverNodes[address].productLow[c], low[c]);
    int carry = previous + low[c] < previous ? 1 : 0;
    if (high[c] + carry != 0) atomicAdd(solverNodes[address].productHigh[c], high[c] + carry);
  }
}

// A node's Hessian product (kg·m/s: β Δt² H u), and its sums cleared for the next product.
vec3 takeProduct(uint address) {
  vec3 sum = fixed64ToFloat(solverNodes[address].productLow, solverNodes[address].productHigh).xyz;
  solverNodes[address].productLow = uvec4(0u);
  solverNodes[address].productHigh = ivec4(0);
  return sum * (solver.w * fixedPoint.y);
}

// --- Constraints -------------------------------------------------------------------------------------------------

// S v: the components the node's constraint leaves free.
vec3 constrain(vec3 v, vec4 constraint) {
  int code = int(constraint.w);
  if ((code & CONSTRAINT_FIXED) != 0) return vec3(0.0);
  if ((code & CONSTRAINT_NORMAL) != 0) v -= dot(v, constraint.xyz) * constraint.xyz;
  ivec3 walls = ivec3(code) & ivec3(CONSTRAINT_WALL_X, 2 * CONSTRAINT_WALL_X, 4 * CONSTRAINT_WALL_X);
  return mix(v, vec3(0.0), notEqual(walls, ivec3(0)));
}

// M⁻¹ for a node of `massKg` (0 for a node without mass, which the constraints hold).
float inverseMass(float massKg) { return massKg > 0.0 ? 1.0 / massKg : 0.0; }
