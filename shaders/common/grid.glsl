// Grid node storage and the P2G scatter, in nondimensional units (design.md, "Fixed-point atomics"):
// mass in units of m_ref, momentum and impulse in units of m_ref·h/Δt_ref (a node moving one cell per step).
//
// FIRN_FLOAT_ATOMICS: float atomicAdd from GL_NV_shader_atomic_float. Otherwise each value is scaled by 2^k
// and rounded to int32; integer sums are exact and order-independent, so runs are bitwise deterministic.
// atomicAdd returns the old value, so a sum that leaves the int32 range is caught the moment it happens.
//
// After update_grid.comp the same storage holds floats: (velocity m/s, mass kg) and, for PIC/FLIP, the
// velocity before forces. FIRN_TRANSFER_APIC needs no second buffer: impulse goes straight into momentum.
#include "common/watchdog.glsl"

#ifdef FIRN_FLOAT_ATOMICS
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

const uint CHANNEL_MASS = 0u;
const uint CHANNEL_MOMENTUM = 1u;
const uint CHANNEL_IMPULSE = 4u;

#ifdef FIRN_FLOAT_ATOMICS

#define FIRN_SCATTER(member, value, node, channel) atomicAdd(member, value)

vec4 storedToNondimensional(vec4 stored) { return stored; }
vec4 storedFloats(vec4 stored) { return stored; }
vec4 floatsToStored(vec4 values) { return values; }

#else

// Largest magnitude a single scaled contribution may have before int() is undefined: 2^31 − 128.
const float FIXED_POINT_LIMIT = 2147483520.0;

int toFixedPoint(float value, uint node, uint channel) {
  float scaled = round(value * fixedPoint.z);
  if (!(abs(scaled) <= FIXED_POINT_LIMIT)) {  // also catches NaN
    reportOverflow(node, channel);
    return 0;
  }
  return int(scaled);
}

// Signed overflow of old + add happened iff old and add share a sign that the sum does not.
#define FIRN_SCATTER(member, value, node, channel)                        \
  {                                                                       \
    int addend = toFixedPoint(value, node, channel);                      \
    int previous = atomicAdd(member, addend);                             \
    if (((previous ^ (previous + addend)) & (addend ^ (previous + addend))) < 0) reportOverflow(node, channel); \
  }

vec4 storedToNondimensional(ivec4 stored) { return vec4(stored) * fixedPoint.w; }
vec4 storedFloats(ivec4 stored) { return intBitsToFloat(stored); }
ivec4 floatsToStored(vec4 values) { return floatBitsToInt(values); }

#endif

// P2G: adds a particle's nondimensional contribution (momentum xyz, mass w) to a node.
void scatterMomentumMass(uint node, vec4 momentumMass) {
  FIRN_SCATTER(gridMomentumMass[node].x, momentumMass.x, node, CHANNEL_MOMENTUM + 0u);
  FIRN_SCATTER(gridMomentumMass[node].y, momentumMass.y, node, CHANNEL_MOMENTUM + 1u);
  FIRN_SCATTER(gridMomentumMass[node].z, momentumMass.z, node, CHANNEL_MOMENTUM + 2u);
  FIRN_SCATTER(gridMomentumMass[node].w, momentumMass.w, node, CHANNEL_MASS);
}

#ifndef FIRN_TRANSFER_APIC
void scatterImpulse(uint node, vec3 impulse) {
  FIRN_SCATTER(gridImpulse[node].x, impulse.x, node, CHANNEL_IMPULSE + 0u);
  FIRN_SCATTER(gridImpulse[node].y, impulse.y, node, CHANNEL_IMPULSE + 1u);
  FIRN_SCATTER(gridImpulse[node].z, impulse.z, node, CHANNEL_IMPULSE + 2u);
}
#endif

// After P2G: the node's nondimensional mass (units of m_ref).
float nodeMassUnits(uint node) { return storedToNondimensional(gridMomentumMass[node]).w; }

// After the grid update: velocity after forces and collisions (m/s).
vec3 nodeVelocity(uint node) { return storedFloats(gridMomentumMass[node]).xyz; }
#ifndef FIRN_TRANSFER_APIC
// After the grid update: velocity before forces (m/s), for the FLIP increment.
vec3 nodeVelocityBeforeForces(uint node) { return storedFloats(gridImpulse[node]).xyz; }
#endif
