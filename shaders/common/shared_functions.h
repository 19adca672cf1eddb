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
#define FIRN_INOUT(type) type&
#define FIRN_GENERIC template <class Real>
#else
#define FIRN_FUNCTION
#define FIRN_OUT(type) out type
#define FIRN_INOUT(type) inout type
#define FIRN_GENERIC
#define Real float
#endif

// The field buffer of the mesh colliders and bodies: the shaders' buffer texture (common/colliders.glsl binds it),
// the host's vector of its floats, passed as the first argument of the functions that read it.
#ifdef __cplusplus
#define FIRN_FIELD_BUFFER const std::vector<float>&fieldBuffer,
#define FIRN_FIELD_PASS fieldBuffer,
#define FIRN_FIELD_VALUE(index) fieldBuffer.at(std::size_t(index))
#else
#ifdef FIRN_HAS_COLLIDER_FIELDS
layout(binding = FIRN_TEXTURE_UNIT_COLLIDER_FIELDS) uniform samplerBuffer colliderFields;
#endif
#define FIRN_FIELD_BUFFER
#define FIRN_FIELD_PASS
#define FIRN_FIELD_VALUE(index) texelFetch(colliderFields, index).r
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

// The elastic strain energy densities Ψ (J per m³ of the undeformed material) of the models, whose derivatives are
// the stresses of common/materials.glsl (docs/numerics.md, The energy audit): the GPU's audit sums V⁰ Ψ over the
// particles (common/energy.glsl), and tests/unit/MaterialsTest.cpp checks each derivative against its stress.
// Fixed corotated (Stomakhin et al. 2013 eq. 5; snow with μ and λ hardened at J_P): μ Σ (σᵢ − 1)² + λ/2 (J − 1)².
FIRN_GENERIC Real fixedCorotatedEnergyDensity(Real muPa, Real lambdaPa, Real sigma1, Real sigma2, Real sigma3) {
  Real J = sigma1 * sigma2 * sigma3;
  return muPa * ((sigma1 - Real(1)) * (sigma1 - Real(1)) + (sigma2 - Real(1)) * (sigma2 - Real(1)) +
                 (sigma3 - Real(1)) * (sigma3 - Real(1))) +
         Real(0.5) * lambdaPa * (J - Real(1)) * (J - Real(1));
}

// Neo-Hookean (Blažević 2022 eq. 4.4): μ/2 (tr FᵀF − 3) − μ ln J + λ/2 (ln J)².
FIRN_GENERIC Real neoHookeanEnergyDensity(Real muPa, Real lambdaPa, Real traceFtF, Real logJ) {
  return Real(0.5) * muPa * (traceFtF - Real(3)) - muPa * logJ + Real(0.5) * lambdaPa * logJ * logJ;
}

// Hencky's, of Drucker–Prager sand's elastic part (Blažević 2022 eq. 4.12), from the logarithms of F_E's singular
// values: μ Σ (ln σᵢ)² + λ/2 (Σ ln σᵢ)².
FIRN_GENERIC Real henckyEnergyDensity(Real muPa, Real lambdaPa, Real logSigma1, Real logSigma2, Real logSigma3) {
  Real traceLog = logSigma1 + logSigma2 + logSigma3;
  return muPa * (logSigma1 * logSigma1 + logSigma2 * logSigma2 + logSigma3 * logSigma3) +
         Real(0.5) * lambdaPa * traceLog * traceLog;
}

// Water's equation of state p = k (J^−γ − 1) as an energy (Blažević 2022 §4.1): Ψ(J) = −∫₁ᴶ p dJ
// = k ((J − 1) − (J^(1−γ) − 1) / (1 − γ)), from l = ln J. Near J = 1 the two terms cancel to k γ l² / 2, so there
// it is summed as the series k Σₙ₌₂ (1 − a^(n−1)) lⁿ / n!, a = 1 − γ, whose terms past n = 8 are below 1e-7 of the
// first while |l| < 1/8 and |a l| < 1/2; elsewhere the two exponentials (a = 0: ln J itself) lose nothing.
FIRN_GENERIC Real waterEnergyDensity(Real bulkModulusPa, Real gamma, Real logJ) {
  Real a = Real(1) - gamma;
  if (abs(logJ) < Real(0.125) && abs(a * logJ) < Real(0.5)) {
    Real sum = Real(0);
    Real term = logJ;         // lⁿ / n!
    Real power = Real(1);     // a^(n−1)
    for (int n = 2; n <= 8; ++n) {
      term *= logJ / Real(n);
      power *= a;
      sum += (Real(1) - power) * term;
    }
    return bulkModulusPa * sum;
  }
  Real scaled = abs(a) > Real(0) ? (exp(a * logJ) - Real(1)) / a : logJ;
  return bulkModulusPa * ((exp(logJ) - Real(1)) - scaled);
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

// The turn `first` followed by `then`: the quaternion product then · first (Hamilton's, xyz the vector part).
FIRN_FUNCTION vec4 composeTurns(vec4 first, vec4 then) {
  vec3 u = vec3(then.x, then.y, then.z), v = vec3(first.x, first.y, first.z);
  vec3 vectorPart = then.w * v + first.w * u + cross(u, v);
  return vec4(vectorPart.x, vectorPart.y, vectorPart.z, then.w * first.w - dot(u, v));
}

// The turn of a body spinning at angularVelocity for durationS: |ω| t about ω's axis, a unit quaternion.
FIRN_FUNCTION vec4 turnOver(vec3 angularVelocity, float durationS) {
  float speed = length(angularVelocity);
  if (!(speed > 0.0f)) return vec4(0.0f, 0.0f, 0.0f, 1.0f);
  float halfAngle = 0.5f * speed * durationS;
  return vec4(angularVelocity * (sin(halfAngle) / speed), cos(halfAngle));
}

// Where a collider's pivot is at timeS: its pose moves rigidly from c.pivotTime.w at v (docs/algorithm.md eq. 33).
FIRN_FUNCTION vec3 colliderPivot(ColliderParams c, float timeS) {
  return vec3(c.pivotTime) + vec3(c.velocity) * (timeS - c.pivotTime.w);
}

// x taken into the frame of a collider's shape at rest, from its pivot, at time timeS (eq. 33): where eq. 27 measures
// the shape.
FIRN_FUNCTION vec3 colliderRestPoint(ColliderParams c, vec3 x, float timeS) {
  vec4 turn = turnOver(vec3(c.angularVelocity), timeS - c.pivotTime.w);
  return rotateByQuaternion(inverseQuaternion(c.rotation),
                            rotateByQuaternion(inverseQuaternion(turn), x - colliderPivot(c, timeS)));
}

// A direction of the shape at rest (a normal) turned into the world at timeS.
FIRN_FUNCTION vec3 colliderWorldDirection(ColliderParams c, vec3 restDirection, float timeS) {
  vec4 turn = turnOver(vec3(c.angularVelocity), timeS - c.pivotTime.w);
  return rotateByQuaternion(turn, rotateByQuaternion(c.rotation, restDirection));
}

// The signed distance φ (m, negative inside) of an analytic shape (plane, sphere, box) at a point of its rest frame,
// and its outward unit normal there (eq. 27).
FIRN_FUNCTION float shapeDistance(ColliderParams c, vec3 fromPivot, FIRN_OUT(vec3) restNormal) {
  if (c.shapeBoundary.x == SHAPE_PLANE) {
    restNormal = vec3(c.shapeB);
    return dot(fromPivot - vec3(c.shapeA), restNormal);
  }
  if (c.shapeBoundary.x == SHAPE_SPHERE) {
    vec3 fromCentre = fromPivot - vec3(c.shapeA);
    float distanceToCentre = length(fromCentre);
    restNormal = distanceToCentre > 0.0f ? fromCentre / distanceToCentre : vec3(0.0f, 1.0f, 0.0f);
    return distanceToCentre - c.shapeA.w;
  }
  vec3 halfExtent = vec3(c.shapeB);
  vec3 fromCentre = fromPivot - vec3(c.shapeA);
  vec3 excess = abs(fromCentre) - halfExtent;  // > 0 on the axes where x lies outside the slab
  if (any(greaterThan(excess, vec3(0.0f)))) {
    vec3 outside = max(excess, vec3(0.0f)) * sign(fromCentre);
    restNormal = normalize(outside);
    return length(outside);
  }
  // Inside: the nearest face decides the normal.
  int axis = excess.x > excess.y ? (excess.x > excess.z ? 0 : 2) : (excess.y > excess.z ? 1 : 2);
  restNormal = vec3(0.0f);
  restNormal[axis] = fromCentre[axis] >= 0.0f ? 1.0f : -1.0f;
  return excess[axis];
}

// Where a point of a mesh collider's rest frame falls in its distance field (ColliderParams.field, fieldOrigin):
// the lattice cell whose samples the trilinear interpolation reads (its low corner, `cell`), the point's place in
// it (`fraction`, in [0, 1]³), and how far the point lies outside the lattice (`outsideM`, 0 inside): the lattice
// covers the mesh with a margin, and beyond it φ grows by that distance (a lower bound, as φ is 1-Lipschitz).
FIRN_FUNCTION void fieldCell(ColliderParams c, vec3 fromPivot, FIRN_OUT(ivec3) cell, FIRN_OUT(vec3) fraction,
                             FIRN_OUT(vec3) outsideM) {
  vec3 highest = vec3(float(c.field.y - 1), float(c.field.z - 1), float(c.field.w - 1));
  vec3 lattice = (fromPivot - vec3(c.fieldOrigin)) / c.fieldOrigin.w;
  vec3 inside = clamp(lattice, vec3(0.0f), highest);
  outsideM = (lattice - inside) * c.fieldOrigin.w;
  cell = ivec3(min(floor(inside), highest - 1.0f));
  fraction = inside - vec3(cell);
}

// The sample index of a lattice point in the field buffer.
FIRN_FUNCTION int fieldSampleIndex(ColliderParams c, ivec3 latticePoint) {
  return c.field.x + (latticePoint.z * c.field.z + latticePoint.y) * c.field.y + latticePoint.x;
}

// φ̃ inside a lattice cell by trilinear interpolation of its corners (corner k at x = k & 1, y = (k >> 1) & 1,
// z = k >> 2), and the direction of its gradient there (eq. 34), or beyond the lattice φ̃ at its nearest point plus
// the distance from there: the side of a point far from the surface, and φ beyond the lattice (meshRestDistance).
FIRN_FUNCTION float cellDistance(float corners[8], vec3 fraction, vec3 outsideM, FIRN_OUT(vec3) restNormal) {
  vec3 f = fraction;
  vec3 g = vec3(1.0f) - f;
  float x00 = g.x * corners[0] + f.x * corners[1], x10 = g.x * corners[2] + f.x * corners[3];
  float x01 = g.x * corners[4] + f.x * corners[5], x11 = g.x * corners[6] + f.x * corners[7];
  float y0 = g.y * x00 + f.y * x10, y1 = g.y * x01 + f.y * x11;
  float distanceM = g.z * y0 + f.z * y1;
  vec3 gradient = vec3(g.y * g.z * (corners[1] - corners[0]) + f.y * g.z * (corners[3] - corners[2]) +
                           g.y * f.z * (corners[5] - corners[4]) + f.y * f.z * (corners[7] - corners[6]),
                       g.z * (x10 - x00) + f.z * (x11 - x01), y1 - y0);
  float outside = length(outsideM);
  if (outside > 0.0f) {
    restNormal = outsideM / outside;
    return distanceM + outside;
  }
  float gradientLength = length(gradient);
  restNormal = gradientLength > 0.0f ? gradient / gradientLength : vec3(0.0f, 1.0f, 0.0f);
  return distanceM;
}

#if defined(__cplusplus) || defined(FIRN_HAS_COLLIDER_FIELDS)
// Three floats of the field buffer from `index` on: a point or a direction.
FIRN_FUNCTION vec3 fieldVector(FIRN_FIELD_BUFFER int index) {
  return vec3(FIRN_FIELD_VALUE(index), FIRN_FIELD_VALUE(index + 1), FIRN_FIELD_VALUE(index + 2));
}
#endif

#if defined(__cplusplus) || defined(FIRN_HAS_MESH_SHAPES)
// The closest point of the triangle abc to p, and which feature of it that is: 0 its face, 1–3 its edges ab, bc, ca,
// 4–6 its corners a, b, c — by the Voronoi regions of its corners, edges and face (Ericson, "Real-Time Collision
// Detection", 2005, §5.1.5). A triangle too flat to have a face region ends at its corner a.
FIRN_FUNCTION vec3 closestPointOnTriangle(vec3 p, vec3 a, vec3 b, vec3 c, FIRN_OUT(int) feature) {
  vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  feature = 4;
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  vec3 bp = p - b;
  float d3 = dot(ab, bp), d4 = dot(ac, bp);
  feature = 5;
  if (d3 >= 0.0f && d4 <= d3) return b;
  float vc = d1 * d4 - d3 * d2;
  feature = 1;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + (d1 / (d1 - d3)) * ab;
  vec3 cp = p - c;
  float d5 = dot(ab, cp), d6 = dot(ac, cp);
  feature = 6;
  if (d6 >= 0.0f && d5 <= d6) return c;
  float vb = d5 * d2 - d1 * d6;
  feature = 3;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + (d2 / (d2 - d6)) * ac;
  float va = d3 * d6 - d5 * d4;
  feature = 2;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  float total = va + vb + vc;
  feature = total > 0.0f ? 0 : 4;
  return total > 0.0f ? a + ab * (vb / total) + ac * (vc / total) : a;
}

// The nearest point of a mesh found so far: its squared distance, where it is, the record of its triangle in the
// field buffer and which feature of it (closestPointOnTriangle).
struct MeshNearest {
  float squaredDistanceM2;
  vec3 pointM;
  int record;
  int feature;
};

// Offers `nearest` the mesh's triangle `triangle` (−1: none), and returns the feature of it nearest the point
// (closestPointOnTriangle; −1 where it was not measured: none, or the nearest already).
FIRN_FUNCTION int offerTriangle(FIRN_FIELD_BUFFER ColliderParams c, vec3 fromPivot, int triangle,
                                FIRN_INOUT(MeshNearest) nearest) {
  int record = c.field.x + 2 * c.field.y * c.field.z * c.field.w + FIELD_TRIANGLE_FLOATS * triangle;
  if (triangle < 0 || record == nearest.record) return -1;
  int feature;
  vec3 pointM = closestPointOnTriangle(fromPivot, fieldVector(FIRN_FIELD_PASS record),
                                       fieldVector(FIRN_FIELD_PASS record + 3), fieldVector(FIRN_FIELD_PASS record + 6),
                                       feature);
  vec3 away = fromPivot - pointM;
  float squaredDistanceM2 = dot(away, away);
  if (feature == 0) {
    // Over the face, the height over its plane: it loses nothing to the barycentric weights' rounding, so a flat
    // face measures as the analytic shape's (the snow on a mesh box is the analytic box's to 10⁻³ h).
    vec3 faceNormal = fieldVector(FIRN_FIELD_PASS record + 9);
    float heightM = dot(fromPivot - fieldVector(FIRN_FIELD_PASS record), faceNormal);
    squaredDistanceM2 = heightM * heightM;
    pointM = fromPivot - heightM * faceNormal;
  }
  if (squaredDistanceM2 < nearest.squaredDistanceM2) {
    nearest.squaredDistanceM2 = squaredDistanceM2;
    nearest.pointM = pointM;
    nearest.record = record;
    nearest.feature = feature;
  }
  return feature;
}

// Offers `nearest` the triangles beyond the edges of a feature (an edge, or a corner's two) of the triangle whose
// record starts at `record`: a point whose nearest feature of one triangle is an edge or a corner lies over a face
// beyond it, or nearest that edge or corner itself.
FIRN_FUNCTION void offerTrianglesAcross(FIRN_FIELD_BUFFER ColliderParams c, vec3 fromPivot, int record, int feature,
                                        FIRN_INOUT(MeshNearest) nearest) {
  if (feature <= 0) return;
  // Edge k (ab, bc, ca) is feature k + 1; corner k (a, b, c), feature k + 4, ends edges k and k + 2 (mod 3).
  int first = feature <= 3 ? feature - 1 : feature - 4;
  int second = feature <= 3 ? first : (first + 2) % 3;
  int firstTriangle = int(FIRN_FIELD_VALUE(record + 30 + first));
  int secondTriangle = int(FIRN_FIELD_VALUE(record + 30 + second));
  offerTriangle(FIRN_FIELD_PASS c, fromPivot, firstTriangle, nearest);
  if (secondTriangle != firstTriangle) offerTriangle(FIRN_FIELD_PASS c, fromPivot, secondTriangle, nearest);
}

// Offers `nearest` the triangle that the field's sample `named` names as its nearest, and those beyond the feature
// of it nearest the point: a sample names one of the faces it is equally near, and a face's triangles meet
// along a diagonal, so the point's nearest face may be the next one over.
FIRN_FUNCTION void offerSampleTriangle(FIRN_FIELD_BUFFER ColliderParams c, vec3 fromPivot, int named,
                                       FIRN_INOUT(MeshNearest) nearest) {
  int sampleCount = c.field.y * c.field.z * c.field.w;
  int triangle = int(FIRN_FIELD_VALUE(named + sampleCount));
  int feature = offerTriangle(FIRN_FIELD_PASS c, fromPivot, triangle, nearest);
  int record = c.field.x + 2 * sampleCount + FIELD_TRIANGLE_FLOATS * triangle;
  offerTrianglesAcross(FIRN_FIELD_PASS c, fromPivot, record, feature, nearest);
}

// A mesh's signed distance φ at a point of its rest frame, and the outward unit normal there (eq. 34). Inside the
// solid and within a cell's diagonal outside it, |φ| is the exact distance to the nearest of the triangles its
// cell's eight samples name and those beyond them (the nearest triangle, but for near ties on medial surfaces), the
// normal points from that triangle's closest point, and the side is that of the closest feature's pseudonormal
// (exact for a closed mesh at its edges and corners, where the trilinear interpolant rounds them off) or, deeper
// than a cell's diagonal inside, the interpolant's (the winding number's, for open meshes). Farther out, and beyond
// the lattice (the interpolant at its nearest point plus the distance from there), the interpolant's.
FIRN_FUNCTION float meshRestDistance(FIRN_FIELD_BUFFER ColliderParams c, vec3 fromPivot, FIRN_OUT(vec3) restNormal) {
  ivec3 cell;
  vec3 fraction, outsideM;
  fieldCell(c, fromPivot, cell, fraction, outsideM);
  // The corners one by one: a loop would spend llvmpipe's iterations per invocation (docs/platform.md).
  int first = fieldSampleIndex(c, cell);
  int row = c.field.y, layer = c.field.y * c.field.z;
  float corners[8];
  corners[0] = FIRN_FIELD_VALUE(first);
  corners[1] = FIRN_FIELD_VALUE(first + 1);
  corners[2] = FIRN_FIELD_VALUE(first + row);
  corners[3] = FIRN_FIELD_VALUE(first + row + 1);
  corners[4] = FIRN_FIELD_VALUE(first + layer);
  corners[5] = FIRN_FIELD_VALUE(first + layer + 1);
  corners[6] = FIRN_FIELD_VALUE(first + layer + row);
  corners[7] = FIRN_FIELD_VALUE(first + layer + row + 1);
  float interpolatedM = cellDistance(corners, fraction, outsideM, restNormal);
  // Farther out than a cell's diagonal no response acts, the interpolant's sign is right and its value within
  // 0.16 s of φ (the rounding of edges; tests/unit/ColliderMotionTest.cpp): it stands, for the eight reads it took.
  float bandM = 1.7320508f * c.fieldOrigin.w;
  if (interpolatedM > bandM || outsideM.x != 0.0f || outsideM.y != 0.0f || outsideM.z != 0.0f) return interpolatedM;
  MeshNearest nearest;
  nearest.squaredDistanceM2 = 3.0e38f;
  nearest.pointM = fromPivot;
  nearest.record = -1;
  nearest.feature = 0;
  offerSampleTriangle(FIRN_FIELD_PASS c, fromPivot, first, nearest);
  offerSampleTriangle(FIRN_FIELD_PASS c, fromPivot, first + 1, nearest);
  offerSampleTriangle(FIRN_FIELD_PASS c, fromPivot, first + row, nearest);
  offerSampleTriangle(FIRN_FIELD_PASS c, fromPivot, first + row + 1, nearest);
  offerSampleTriangle(FIRN_FIELD_PASS c, fromPivot, first + layer, nearest);
  offerSampleTriangle(FIRN_FIELD_PASS c, fromPivot, first + layer + 1, nearest);
  offerSampleTriangle(FIRN_FIELD_PASS c, fromPivot, first + layer + row, nearest);
  offerSampleTriangle(FIRN_FIELD_PASS c, fromPivot, first + layer + row + 1, nearest);
  // Once more beyond the nearest found: a face's own two triangles may lie beyond the one a sample named.
  offerTrianglesAcross(FIRN_FIELD_PASS c, fromPivot, nearest.record, nearest.feature, nearest);
  vec3 away = fromPivot - nearest.pointM;
  float distanceM = sqrt(nearest.squaredDistanceM2);
  vec3 pseudonormal = fieldVector(FIRN_FIELD_PASS nearest.record + 9 + 3 * nearest.feature);
  float spacingM = c.fieldOrigin.w;
  float side = interpolatedM < -bandM ? -1.0f : dot(away, pseudonormal) < 0.0f ? -1.0f : 1.0f;
  // On the surface (to the float rounding of positions, far below 10⁻⁴ spacings) the direction of `away` is noise.
  restNormal = distanceM > 1e-4f * spacingM ? away * (side / distanceM) : pseudonormal;
  return side * distanceM;
}
#endif

// The velocity of a collider's surface at x at timeS, the rigid motion's v + ω × (x − c(t)) (eq. 33).
FIRN_FUNCTION vec3 colliderVelocity(ColliderParams c, vec3 x, float timeS) {
  return vec3(c.velocity) + cross(vec3(c.angularVelocity), x - colliderPivot(c, timeS));
}

#ifndef __cplusplus
#undef Real
#endif

#endif
