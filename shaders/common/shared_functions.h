// Functions the host and the shaders both evaluate, written once in the part of C++17 and GLSL 4.30 they have
// in common (no swizzles, float literals with an f). The GPU uses them every step; the host before running
// (the pre-flight check of engine/run/Preflight.cpp, the first adaptive step, the watchdog's advice).
// C++ reads this file through engine/gpu/GpuFunctions.h, inside namespace firn::gpu with glm's functions.
// FIRN_FUNCTION marks a function (inline in C++); FIRN_GENERIC ones are templates in C++, so the host evaluates
// them in double precision, and float functions in GLSL.
#ifndef FIRN_SHARED_FUNCTIONS_H
#define FIRN_SHARED_FUNCTIONS_H

#include "common/gpu_contract.h"

#ifdef __cplusplus
#define FIRN_FUNCTION inline
#define FIRN_OUT(type) type&
#define FIRN_GENERIC template <class Real>
#else
#define FIRN_FUNCTION
#define FIRN_OUT(type) out type
#define FIRN_GENERIC
#define Real float
#endif

// The speed of the fastest elastic (pressure) wave in a solid, sqrt((λ + 2μ) / ρ), with its moduli stiffened
// by `stiffening` (snow's hardening e^{ξ(1 − J_P)}, Stomakhin et al. 2013 eq. 7; 1 for other solids).
FIRN_GENERIC Real pressureWaveSpeed(Real lambdaPa, Real muPa, Real stiffening, Real densityKgPerM3) {
  return sqrt((lambdaPa + Real(2) * muPa) * stiffening / densityKgPerM3);
}

// Water's wave speed, sqrt(k γ / ρ): dp/dJ at rest of the pressure p = k (J^−γ − 1).
FIRN_GENERIC Real waterWaveSpeed(Real bulkModulusPa, Real gamma, Real densityKgPerM3) {
  return sqrt(bulkModulusPa * gamma / densityKgPerM3);
}

// The most particles a transfer's tile of base nodes may hold (common/blocks.glsl): llvmpipe ends a shader
// invocation's loops after 65,535 iterations in all, silently (docs/platform.md), and a transfer spends one per row
// of the stencil along x and particle (KERNEL_WIDTH²), a few more per particle (the particle loop, the SVD's sweeps,
// the colliders) and a few hundred per tile (its accumulators); 60,000 / (KERNEL_WIDTH² + 16) leaves room for it.
FIRN_FUNCTION uint maxTileParticles(int kernelWidth) { return 60000u / uint(kernelWidth * kernelWidth + 16); }

// A collider's signed distance φ at x (m, negative inside its solid) and the outward unit normal there, at
// time timeS: colliders translate at their velocity.
FIRN_FUNCTION float colliderDistance(ColliderParams c, vec3 x, float timeS, FIRN_OUT(vec3) normal) {
  vec3 displacement = vec3(c.velocityFriction) * timeS;
  if (c.shapeBoundary.x == SHAPE_PLANE) {
    normal = vec3(c.geometryB);
    return dot(x - (vec3(c.geometryA) + displacement), normal);
  }
  if (c.shapeBoundary.x == SHAPE_SPHERE) {
    vec3 fromCentre = x - (vec3(c.geometryA) + displacement);
    float distanceToCentre = length(fromCentre);
    normal = distanceToCentre > 0.0f ? fromCentre / distanceToCentre : vec3(0.0f, 1.0f, 0.0f);
    return distanceToCentre - c.geometryA.w;
  }
  vec3 centre = 0.5f * (vec3(c.geometryA) + vec3(c.geometryB)) + displacement;
  vec3 halfExtent = 0.5f * (vec3(c.geometryB) - vec3(c.geometryA));
  vec3 fromCentre = x - centre;
  vec3 excess = abs(fromCentre) - halfExtent;  // > 0 on the axes where x lies outside the slab
  if (any(greaterThan(excess, vec3(0.0f)))) {
    vec3 outside = max(excess, vec3(0.0f)) * sign(fromCentre);
    normal = normalize(outside);
    return length(outside);
  }
  // Inside: the nearest face decides the normal.
  int axis = excess.x > excess.y ? (excess.x > excess.z ? 0 : 2) : (excess.y > excess.z ? 1 : 2);
  normal = vec3(0.0f);
  normal[axis] = fromCentre[axis] >= 0.0f ? 1.0f : -1.0f;
  return excess[axis];
}

#ifndef __cplusplus
#undef Real
#endif

#endif
