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

// Snow's hardening, e^{ξ(1 − J_P)} (Stomakhin et al. 2013 eq. 7): the factor its Lamé parameters take at J_P.
FIRN_GENERIC Real snowHardening(Real hardening, Real plasticJ) { return exp(hardening * (Real(1) - plasticJ)); }

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

// v rotated by the unit quaternion q (xyz its vector part u, w its scalar part): v + w t + u × t, t = 2 u × v.
FIRN_FUNCTION vec3 rotateByQuaternion(vec4 q, vec3 v) {
  vec3 u = vec3(q.x, q.y, q.z);
  vec3 t = 2.0f * cross(u, v);
  return v + q.w * t + cross(u, t);
}

FIRN_FUNCTION vec4 inverseQuaternion(vec4 q) { return vec4(-q.x, -q.y, -q.z, q.w); }

// The turn of a body spinning at angularVelocity for durationS: |ω| t about ω's axis, a unit quaternion.
FIRN_FUNCTION vec4 turnOver(vec3 angularVelocity, float durationS) {
  float speed = length(angularVelocity);
  if (!(speed > 0.0f)) return vec4(0.0f, 0.0f, 0.0f, 1.0f);
  float halfAngle = 0.5f * speed * durationS;
  return vec4(angularVelocity * (sin(halfAngle) / speed), cos(halfAngle));
}

// Where a collider's pivot is at timeS: its pose moves rigidly from c.pivotTime.w at v (docs/algorithm.md eq. 33).
FIRN_FUNCTION vec3 colliderPivot(ColliderParams c, float timeS) {
  return vec3(c.pivotTime) + vec3(c.velocityFriction) * (timeS - c.pivotTime.w);
}

// A collider's signed distance φ at x (m, negative inside its solid) and the outward unit normal there, at
// time timeS: x is taken into the frame of the shape at rest (eq. 33), measured there (eq. 27), and the normal
// turned back into the world.
FIRN_FUNCTION float colliderDistance(ColliderParams c, vec3 x, float timeS, FIRN_OUT(vec3) normal) {
  vec4 turn = turnOver(vec3(c.angularVelocity), timeS - c.pivotTime.w);
  vec3 fromPivot = rotateByQuaternion(inverseQuaternion(c.rotation),
                                      rotateByQuaternion(inverseQuaternion(turn), x - colliderPivot(c, timeS)));
  vec3 restNormal;
  float signedDistance;
  if (c.shapeBoundary.x == SHAPE_PLANE) {
    restNormal = vec3(c.shapeB);
    signedDistance = dot(fromPivot - vec3(c.shapeA), restNormal);
  } else if (c.shapeBoundary.x == SHAPE_SPHERE) {
    vec3 fromCentre = fromPivot - vec3(c.shapeA);
    float distanceToCentre = length(fromCentre);
    restNormal = distanceToCentre > 0.0f ? fromCentre / distanceToCentre : vec3(0.0f, 1.0f, 0.0f);
    signedDistance = distanceToCentre - c.shapeA.w;
  } else {
    vec3 halfExtent = vec3(c.shapeB);
    vec3 fromCentre = fromPivot - vec3(c.shapeA);
    vec3 excess = abs(fromCentre) - halfExtent;  // > 0 on the axes where x lies outside the slab
    if (any(greaterThan(excess, vec3(0.0f)))) {
      vec3 outside = max(excess, vec3(0.0f)) * sign(fromCentre);
      restNormal = normalize(outside);
      signedDistance = length(outside);
    } else {
      // Inside: the nearest face decides the normal.
      int axis = excess.x > excess.y ? (excess.x > excess.z ? 0 : 2) : (excess.y > excess.z ? 1 : 2);
      restNormal = vec3(0.0f);
      restNormal[axis] = fromCentre[axis] >= 0.0f ? 1.0f : -1.0f;
      signedDistance = excess[axis];
    }
  }
  normal = rotateByQuaternion(turn, rotateByQuaternion(c.rotation, restNormal));
  return signedDistance;
}

// The velocity of a collider's surface at x at timeS, the rigid motion's v + ω × (x − c(t)) (eq. 33).
FIRN_FUNCTION vec3 colliderVelocity(ColliderParams c, vec3 x, float timeS) {
  return vec3(c.velocityFriction) + cross(vec3(c.angularVelocity), x - colliderPivot(c, timeS));
}

#ifndef __cplusplus
#undef Real
#endif

#endif
