// Grid node storage and the P2G scatter, in nondimensional units (docs/numerics.md, Fixed-point atomics):
// mass in units of m_ref, momentum and impulse in units of m_ref·h/Δt_ref (a node moving one cell per step).
//
// FIRN_FLOAT_ATOMICS: float atomicAdd from GL_NV_shader_atomic_float. FIRN_P2G_BLOCKS: plain float additions,
// race-free because no two invocations of a pass reach one node (common/blocks.glsl).
// Otherwise each value is scaled by 2^k and rounded to int32; integer sums are exact and order-independent, so
// runs are bitwise deterministic. atomicAdd returns the old value, so a sum that leaves the int32 range is
// caught the moment it happens.
//
// Rounding to 2^-k is dithered, floor(x·2^k + u) with u uniform in [0, 1): its expectation is x, so slow
// motion — a small fraction of a cell per step, whose contributions are a few quanta each — does not lose
// momentum to rounding bias (plain rounding measurably slowed a freely falling block by 1e-4 in 200 steps).
// u is one hash per particle and step (of its position, not its index, so reordering the particles changes no
// sum), spread over its stencil nodes and channels by additive recurrences with irrational steps, u_nc =
// fract(u_p + n·φ + c·ψ): each u_nc is uniform over particles, which is all unbiased rounding needs, and it
// costs an add per contribution where a hash per contribution cost 40% of P2G on llvmpipe. The dither depends
// only on which contribution it is, so sums stay exact, order-independent and deterministic.
//
// After update_grid.comp the same storage holds floats: (velocity m/s, mass kg) and, for PIC/FLIP, the
// velocity before forces. FIRN_TRANSFER_APIC needs no second buffer: impulse goes straight into momentum.
#include "common/watchdog.glsl"

#if defined(FIRN_FLOAT_ATOMICS) || defined(FIRN_P2G_BLOCKS)
#define FIRN_FLOAT_GRID_SUMS
#endif

#ifdef FIRN_FLOAT_GRID_SUMS
#define GridVector vec4
#else
#define GridVector ivec4
#endif

layout(std430, binding = FIRN_BINDING_GRID_MOMENTUM_MASS) coherent buffer GridMomentumMassBuffer {
  GridVector gridMomentumMass[];
};
#ifndef FIRN_TRANSFER_APIC
layout(std430, binding = FIRN_BINDING_GRID_IMPULSE) coherent buffer GridImpulseBuffer { GridVector gridImpulse[]; };
#endif

#ifdef FIRN_FLOAT_GRID_SUMS

#define FIRN_SCATTER(member, value, node, channel, dither) atomicAdd(member, value)

float particleDither(vec3 particlePosition) { return 0.0; }  // float sums are not dithered
float contributionDither(float particleU, int stencilNode) { return 0.0; }
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
  uint hash = mixBits(bits.x ^ mixBits(bits.y ^ mixBits(bits.z ^ mixBits(stepIndex()))));
  return float(hash >> 8) * (1.0 / 16777216.0);  // 24 bits
}

// The dither of the particle's contributions to stencil node n (channel 0), by the golden-ratio recurrence.
float contributionDither(float particleU, int stencilNode) { return fract(particleU + float(stencilNode) * 0.61803399); }

int toFixedPoint(float value, uint node, uint channel, float dither) {
  // Channels step by 1/ρ (ρ the plastic number), incommensurate with the nodes' φ.
  float scaled = floor(value * fixedPoint.z + fract(dither + float(channel) * 0.75487767));
  if (!(abs(scaled) <= FIXED_POINT_LIMIT)) {  // also catches NaN
    reportOverflow(node, channel);
    return 0;
  }
  return int(scaled);
}

// Signed overflow of old + add happened iff old and add share a sign that the sum does not.
#define FIRN_SCATTER(member, value, node, channel, dither)                \
  {                                                                       \
    int addend = toFixedPoint(value, node, channel, dither);              \
    int previous = atomicAdd(member, addend);                             \
    if (((previous ^ (previous + addend)) & (addend ^ (previous + addend))) < 0) reportOverflow(node, channel); \
  }

vec4 storedToNondimensional(ivec4 stored) { return vec4(stored) * fixedPoint.w; }
vec4 storedFloats(ivec4 stored) { return intBitsToFloat(stored); }
ivec4 floatsToStored(vec4 values) { return floatBitsToInt(values); }

#endif

// P2G: adds a particle's nondimensional contribution (momentum xyz, mass w) to a node; `dither` is the
// contribution's contributionDither().
#ifdef FIRN_P2G_BLOCKS
// Whole vectors: no other invocation reaches the node meanwhile (blocks.glsl).
void scatterMomentumMass(uint node, vec4 momentumMass, float dither) { gridMomentumMass[node] += momentumMass; }
#ifndef FIRN_TRANSFER_APIC
void scatterImpulse(uint node, vec3 impulse, float dither) { gridImpulse[node].xyz += impulse; }
#endif
#else
void scatterMomentumMass(uint node, vec4 momentumMass, float dither) {
  FIRN_SCATTER(gridMomentumMass[node].x, momentumMass.x, node, CHANNEL_MOMENTUM + 0u, dither);
  FIRN_SCATTER(gridMomentumMass[node].y, momentumMass.y, node, CHANNEL_MOMENTUM + 1u, dither);
  FIRN_SCATTER(gridMomentumMass[node].z, momentumMass.z, node, CHANNEL_MOMENTUM + 2u, dither);
  FIRN_SCATTER(gridMomentumMass[node].w, momentumMass.w, node, CHANNEL_MASS, dither);
}

#ifndef FIRN_TRANSFER_APIC
void scatterImpulse(uint node, vec3 impulse, float dither) {
  FIRN_SCATTER(gridImpulse[node].x, impulse.x, node, CHANNEL_IMPULSE + 0u, dither);
  FIRN_SCATTER(gridImpulse[node].y, impulse.y, node, CHANNEL_IMPULSE + 1u, dither);
  FIRN_SCATTER(gridImpulse[node].z, impulse.z, node, CHANNEL_IMPULSE + 2u, dither);
}
#endif
#endif

// After P2G: the node's nondimensional mass (units of m_ref).
float nodeMassUnits(uint node) { return storedToNondimensional(gridMomentumMass[node]).w; }

// After the grid update: velocity after forces and collisions (m/s).
vec3 nodeVelocity(uint node) { return storedFloats(gridMomentumMass[node]).xyz; }
#ifndef FIRN_TRANSFER_APIC
// After the grid update: velocity before forces (m/s), for the FLIP increment.
vec3 nodeVelocityBeforeForces(uint node) { return storedFloats(gridImpulse[node]).xyz; }
#endif
