// Rigid bodies as unknowns of the semi-implicit solve (docs/algorithm.md, Rigid bodies in the semi-implicit step).
//
// A node that one body alone holds (its CONSTRAINT_BODY_SHIFT bits; update_grid.comp) keeps its held components on
// the body's surface: x_i = S_i x_i + P_i G_i u, G_i the 3×6 map from the body's velocities u = (V, ω) to its surface's
// velocity at the node, V + ω × (x_i − c), and P_i = I − S_i what the body holds of it (all of it if sticky, its
// normal component if slip or separating). With T the map from the unknowns y = (the nodes' free components, u) to
// the grid's velocities, the solve minimizes ½ (x − v*)ᵀ M (x − v*) + ½ β Δt² xᵀ H x + ½ (u − u*)ᵀ M_b (u − u*) over y,
//
//   (Tᵀ (M + β Δt² H) T + M_b) y = Tᵀ M v* + M_b u*,                                                         (39a)
//
// symmetric positive definite, so the conjugate residual method solves it as it solves the nodes alone: a node's
// vectors keep their free components and, at the nodes a body holds, the held components P_i G_i of the body's own
// (solver_step.comp writes them), so a product of the grid's vectors is a product of T y; the body's rows of a
// product are Σ_i G_iᵀ P_i (A T y)_i over its nodes plus M_b y_b. Each node adds its part to the body's sums here, in
// the solve's 64-bit fixed point, so the sums do not depend on the order of the additions.
#include "common/fixed64.glsl"
#include "common/body_blocks.glsl"

// P_i w: the components of w that the node's constraint holds (for a node a body alone holds, what the body holds).
vec3 heldPart(vec3 w, vec4 constraint) { return w - constrain(w, constraint); }

// The held components of the body's surface velocity at node x for the body's velocities (V, ω): P_i G_i u.
vec3 heldBodyMotion(int b, vec3 x, vec3 linear, vec3 angular, vec4 constraint) {
  vec3 fromCentre = x - colliderPivot(colliders[bodyEntry(b)], timeS);
  return heldPart(linear + cross(angular, fromCentre), constraint);
}

// Node x's place from body b's centre of mass, in cells (the body's sums' unit of length).
vec3 fromBodyCentreCells(int b, vec3 x) { return (x - colliderPivot(colliders[bodyEntry(b)], timeS)) * cellsPerM; }

// Adds G_iᵀ w to body b's sums for a held vector w at `node`, `fromCentreCells` from its centre of mass: w (kg·m/s)
// and its moment. A value beyond the fixed point's range is dropped and the watchdog told, as the products' are.
void addToBodySums(int b, vec3 fromCentreCells, vec3 heldKgMPerS, ivec3 node) {
  float unitsPerKgMPerS = 1.0 / momentumUnitKgMPerS;
  uvec4 low;
  ivec4 high;
  bool fits = productToFixed64(vec4(heldKgMPerS * unitsPerKgMPerS, 0.0), low, high);
  FIRN_ADD_FIXED64(bodyRecords[b].sumsLow[0], bodyRecords[b].sumsHigh[0], low, high)
  fits = productToFixed64(vec4(cross(fromCentreCells, heldKgMPerS) * unitsPerKgMPerS, 0.0), low, high) && fits;
  FIRN_ADD_FIXED64(bodyRecords[b].sumsLow[1], bodyRecords[b].sumsHigh[1], low, high)
  if (!fits) reportOverflow(nodeIndex(node), CHANNEL_SOLVER);
}

// The body's sums as G_iᵀ (kg·m/s) and their moments (kg·m²/s); the sums are cleared for the next product.
void takeBodySums(int b, out vec3 forceKgMPerS, out vec3 momentKgM2PerS) {
  float kgMPerSPerUnit = ldexp(1.0, -solverFractionBits) * momentumUnitKgMPerS;
  forceKgMPerS = fixed64ToFloat(bodyRecords[b].sumsLow[0], bodyRecords[b].sumsHigh[0]).xyz * kgMPerSPerUnit;
  momentKgM2PerS =
      fixed64ToFloat(bodyRecords[b].sumsLow[1], bodyRecords[b].sumsHigh[1]).xyz * (kgMPerSPerUnit * cellSizeM);
  for (int k = 0; k < 2; ++k) {
    bodyRecords[b].sumsLow[k] = uvec4(0u);
    bodyRecords[b].sumsHigh[k] = ivec4(0);
  }
}

// Adds the share of body b's preconditioner block of a node `fromCentreCells` from its centre of mass, G_iᵀ P_i (m I +
// K) P_i G_i with K = β Δt² Hᵢᵢ (kg), the upper triangle of 21 values in P2G's nondimensional units, as the explicit
// step's coupled solve sums Σ m Gᵀ P G (common/body_blocks.glsl, addToCoupling): the body's own diagonal block of eq.
// 39a.
void addToBodyBlock(int b, vec3 fromCentreCells, float massKg, mat3 stiffnessKg, vec4 constraint) {
  mat3 nodeBlock = (massKg * mat3(1.0) + stiffnessKg) * massUnitsPerKg;
  vec3 columns[6];
  for (int k = 0; k < 3; ++k) {
    vec3 axis = vec3(0.0);
    axis[k] = 1.0;
    columns[k] = heldPart(axis, constraint);
    columns[3 + k] = heldPart(cross(axis, fromCentreCells), constraint);  // ∂(ω × r)/∂ω_k
  }
  float sums[24];
  int n = 0;
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c) sums[n++] = dot(columns[r], nodeBlock * columns[c]);
  }
  for (; n < 24; ++n) sums[n] = 0.0;
  float unitsPerValue = ldexp(1.0, COUPLING_FRACTION_BITS);
  for (int w = 0; w < 6; ++w) {
    uvec4 low;
    ivec4 high;
    splitFixed64(round(vec4(sums[4 * w], sums[4 * w + 1], sums[4 * w + 2], sums[4 * w + 3]) * unitsPerValue), low,
                 high);
    FIRN_ADD_FIXED64(bodyRecords[b].blockLow[w], bodyRecords[b].blockHigh[w], low, high)
  }
}

// M_b u for body b: M V and I ω (kg·m/s, kg·m²/s), I in the world's axes now.
void bodyMassTimes(int b, vec3 linear, vec3 angular, out vec3 force, out vec3 moment) {
  force = bodyRecords[b].massRadius.x * linear;
  moment = worldInertia(b) * angular;
}

// The dot product of two of the body's 6-vectors, each as its two parts.
float bodyDot(vec3 a0, vec3 a1, vec3 b0, vec3 b1) { return dot(a0, b0) + dot(a1, b1); }
