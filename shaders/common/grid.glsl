// Grid node storage and the P2G sums, in nondimensional units (docs/numerics.md, "Fixed-point atomics"): mass in
// units of m_ref, momentum and impulse in units of m_ref·h/Δt_ref (a node moving one cell per step). Nodes live in
// the blocks of the pool (common/blocks.glsl): a node's storage index is its address there.
//
// P2G sums each row's particles into private accumulators (p2g.comp), then adds each accumulator to its node with
// one atomicAdd per channel. With fixed point (the default) every contribution is scaled by 2^k and rounded to an
// int32 before it is summed: integer sums are exact and order-independent, so runs are bitwise deterministic, and
// give the same sums as adding every contribution to the node directly. A sum that leaves the int32 range is caught
// the moment it happens, in the accumulator or at the node. FIRN_FLOAT_ATOMICS sums floats instead, with
// GL_NV_shader_atomic_float at the node.
//
// Rounding to 2^-k is dithered, floor(x·2^k + u) with u uniform in [0, 1), taken exactly (quantize): its
// expectation is x, so slow motion — a small fraction of a cell per step, whose contributions are a few quanta
// each — does not lose momentum to rounding bias (plain rounding measurably slowed a freely falling block by 1e-4
// in 200 steps).
// u is one hash per particle and step (of its position, not its index, so reordering the particles changes no
// sum), spread over its stencil nodes and channels by additive recurrences with irrational steps, u_nc =
// fract(u_p + n·φ + c·ψ): each u_nc is uniform over particles, which is all unbiased rounding needs, and it
// costs an add per contribution where a hash per contribution was P2G's largest cost on llvmpipe (docs/platform.md,
// Timing on llvmpipe). The dither depends
// only on which contribution it is, so sums stay exact, order-independent and deterministic.
//
// After update_grid.comp the same storage holds floats: (velocity m/s, mass kg) and, in the impulse's storage, the
// velocity before forces.
#include "common/watchdog.glsl"

// The impulse has storage of its own wherever a pass needs the velocity before forces: PIC/FLIP's increment (g2p.comp)
// and the semi-implicit solve's start (update_grid.comp). An explicit APIC step adds it straight to the momentum. A
// pass that reads neither defines FIRN_WITHOUT_GRID_IMPULSE: llvmpipe counts every storage block declared
// (docs/platform.md).
#if (!defined(FIRN_TRANSFER_APIC) || defined(FIRN_SEMI_IMPLICIT)) && !defined(FIRN_WITHOUT_GRID_IMPULSE)
#define FIRN_GRID_IMPULSE
#endif

#ifdef FIRN_FLOAT_ATOMICS
#define GridVector vec4
#else
#define GridVector ivec4
#endif

layout(std430, binding = FIRN_BINDING_GRID_MOMENTUM_MASS) coherent buffer GridMomentumMassBuffer {
  GridVector gridMomentumMass[];
};
#ifdef FIRN_GRID_IMPULSE
layout(std430, binding = FIRN_BINDING_GRID_IMPULSE) coherent buffer GridImpulseBuffer { GridVector gridImpulse[]; };
#endif

// The watchdog's channel of each component: momentum x, y, z and mass; impulse x, y, z.
const uvec4 MOMENTUM_MASS_CHANNELS = uvec4(CHANNEL_MOMENTUM, CHANNEL_MOMENTUM + 1u, CHANNEL_MOMENTUM + 2u, CHANNEL_MASS);
const uvec4 IMPULSE_CHANNELS = uvec4(CHANNEL_IMPULSE, CHANNEL_IMPULSE + 1u, CHANNEL_IMPULSE + 2u, CHANNEL_IMPULSE);

#ifdef FIRN_FLOAT_ATOMICS

float particleDither(vec3 particlePosition) { return 0.0; }  // float sums are not dithered
float contributionDither(float particleU, int stencilNode) { return 0.0; }
vec4 quantize(vec4 values, uvec4 channels, float dither, inout ivec4 overflow) { return values; }
void accumulate(inout vec4 sum, vec4 addend, inout ivec4 overflow) { sum += addend; }
void reportAccumulatorOverflow(ivec4 overflow, ivec3 node, uvec4 channels) {}
void addToNode(uint address, vec4 momentumMass, ivec3 node) {
  atomicAdd(gridMomentumMass[address].x, momentumMass.x);
  atomicAdd(gridMomentumMass[address].y, momentumMass.y);
  atomicAdd(gridMomentumMass[address].z, momentumMass.z);
  atomicAdd(gridMomentumMass[address].w, momentumMass.w);
}
#ifdef FIRN_GRID_IMPULSE
void addImpulseToNode(uint address, vec3 impulse, ivec3 node) {
  atomicAdd(gridImpulse[address].x, impulse.x);
  atomicAdd(gridImpulse[address].y, impulse.y);
  atomicAdd(gridImpulse[address].z, impulse.z);
}
#endif
vec4 storedToNondimensional(vec4 stored) { return stored; }
vec4 storedFloats(vec4 stored) { return stored; }
vec4 floatsToStored(vec4 values) { return values; }

#else

// Largest magnitude a single scaled contribution may have before int() is undefined: 2^31 − 128.
const float FIXED_POINT_LIMIT = 2147483520.0;

// A well-mixing 32-bit integer hash (the "lowbias32" finaliser).
uint mixBits(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// u_p: the particle's dither in this step, uniform in [0, 1).
float particleDither(vec3 particlePosition) {
  uvec3 bits = floatBitsToUint(particlePosition);
  uint hash = mixBits(bits.x ^ mixBits(bits.y ^ mixBits(bits.z ^ mixBits(stepIndex))));
  return float(hash >> 8) * (1.0 / 16777216.0);  // 24 bits
}

// The dither of the particle's contributions to stencil node n (channel 0), by the golden-ratio recurrence.
float contributionDither(float particleU, int stencilNode) {
  precise float u = fract(particleU + float(stencilNode) * 0.61803399);  // as the weights: the same in every program
  return u;
}

// Reports an overflow of the channels `over` marks at `node`.
void reportOverflows(bvec4 over, ivec3 node, uvec4 channels) {
  for (int c = 0; c < 4; ++c) {
    if (over[c]) reportOverflow(nodeIndex(node), channels[c]);
  }
}

// Contributions in units of 2^-k, channel by channel (channels step their dither by 1/ρ, ρ the plastic number,
// incommensurate with the nodes' φ). One too large for an int32 is dropped, and marked in `overflow` (its sign
// bit, per channel) for the accumulator's node to report: no branch per contribution.
//
// ⌊x·2^k + u⌋ is taken as ⌊x·2^k⌋ + (frac ≥ 1 − u), never as a float sum: x·2^k + u rounds to the float spacing s
// of x·2^k, up to the next integer whenever it falls within s/2 below one, so a sum in float is biased by +s/2
// (about 2⁻²⁵ of the value) and, at a node, by that against the mass and the momentum alike: a freely falling
// particle lost 5e-4 of its speed in 10,000 steps. x·2^k − ⌊x·2^k⌋ is exact (Sterbenz) except for x·2^k in (−1, 0),
// and 1 − u (u ≥ 2⁻²⁴) is off by at most 2⁻²⁵: biases of 2⁻²⁵ of a quantum.
ivec4 quantize(vec4 values, uvec4 channels, float dither, inout ivec4 overflow) {
  precise vec4 exact = values * ldexp(1.0, fixedPointFractionBits);
  vec4 whole = floor(exact);
  precise vec4 u = fract(dither + vec4(channels) * 0.75487767);
  vec4 scaled = whole + vec4(greaterThanEqual(exact - whole, 1.0 - u));
  bvec4 tooLarge = not(lessThanEqual(abs(scaled), vec4(FIXED_POINT_LIMIT)));  // also catches NaN
  overflow |= ivec4(uvec4(tooLarge) << 31);
  return ivec4(mix(scaled, vec4(0.0), tooLarge));
}

// Signed overflow of a + b happened iff a and b share a sign that the sum does not: the sign bit of
// (a ^ sum) & (b ^ sum), kept in `overflow`.
void accumulate(inout ivec4 sum, ivec4 addend, inout ivec4 overflow) {
  ivec4 total = sum + addend;
  overflow |= (sum ^ total) & (addend ^ total);
  sum = total;
}

// Reports the channels an accumulator's `overflow` marks, at its node.
void reportAccumulatorOverflow(ivec4 overflow, ivec3 node, uvec4 channels) {
  bvec4 over = lessThan(overflow, ivec4(0));
  if (any(over)) reportOverflows(over, node, channels);
}

// Signed overflow of a + b, as above.
bvec4 overflowed(ivec4 a, ivec4 b, ivec4 sum) { return lessThan((a ^ sum) & (b ^ sum), ivec4(0)); }

void addToNode(uint address, ivec4 momentumMass, ivec3 node) {
  ivec4 previous = ivec4(0);
  for (int c = 0; c < 4; ++c) {
    if (momentumMass[c] != 0) previous[c] = atomicAdd(gridMomentumMass[address][c], momentumMass[c]);
  }
  bvec4 over = overflowed(previous, momentumMass, previous + momentumMass);
  if (any(over)) reportOverflows(over, node, MOMENTUM_MASS_CHANNELS);
}
#ifdef FIRN_GRID_IMPULSE
void addImpulseToNode(uint address, ivec3 impulse, ivec3 node) {
  ivec4 previous = ivec4(0);
  for (int c = 0; c < 3; ++c) {
    if (impulse[c] != 0) previous[c] = atomicAdd(gridImpulse[address][c], impulse[c]);
  }
  bvec4 over = overflowed(previous, ivec4(impulse, 0), previous + ivec4(impulse, 0));
  if (any(over)) reportOverflows(over, node, IMPULSE_CHANNELS);
}
#endif

vec4 storedToNondimensional(ivec4 stored) { return vec4(stored) * ldexp(1.0, -fixedPointFractionBits); }
vec4 storedFloats(ivec4 stored) { return intBitsToFloat(stored); }
ivec4 floatsToStored(vec4 values) { return floatBitsToInt(values); }

#endif

// After P2G: the node's nondimensional mass (units of m_ref).
float nodeMassUnits(uint address) { return storedToNondimensional(gridMomentumMass[address]).w; }

// After the grid update: velocity after forces and collisions (m/s).
vec3 nodeVelocity(uint address) { return storedFloats(gridMomentumMass[address]).xyz; }
#ifdef FIRN_GRID_IMPULSE
// After the grid update: velocity before forces (m/s), for the FLIP increment.
vec3 nodeVelocityBeforeForces(uint address) { return storedFloats(gridImpulse[address]).xyz; }
#endif
