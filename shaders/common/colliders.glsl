// Signed-distance colliders and the boundary response shared by grid nodes and particles
// (Stomakhin et al. 2013 §8; Blažević 2022 ch. 5; Snow thesis 2015 §4.4). Colliders move rigidly: a surface point
// moves at v + ω × (x − c(t)) (docs/algorithm.md eq. 33).

#include "common/shared_functions.h"
// Outside the #ifdef below: the shader library includes a file once, wherever it first appears, and the
// preprocessor's branches come after that (a later include of it in an active branch would find nothing).
#include "common/fixed64.glsl"
// The work and loads the colliders' responses move (common/energy.glsl).
#include "common/energy.glsl"

#ifdef FIRN_HAS_RIGID_BODIES
// The bodies' entries gather the snow's impulses (pushRigidBody).
layout(std430, binding = FIRN_BINDING_COLLIDERS) buffer CollidersBuffer { ColliderParams colliders[]; };
#else
layout(std430, binding = FIRN_BINDING_COLLIDERS) readonly buffer CollidersBuffer { ColliderParams colliders[]; };
#endif
// A collider's signed distance φ (m, negative inside its solid) at a point of the frame of its shape at rest,
// `fromPivot`, and the outward unit normal there in that frame: an analytic shape by eq. 27, a mesh by its distance
// field (eq. 34).
float colliderRestDistance(ColliderParams c, vec3 fromPivot, out vec3 restNormal) {
#ifdef FIRN_HAS_MESH_SHAPES
  if (c.shapeBoundary.x == SHAPE_MESH) return meshRestDistance(c, fromPivot, restNormal);
#endif
  return shapeDistance(c, fromPivot, restNormal);
}

// A collider's signed distance φ at x (m, negative inside its solid) and the outward unit normal there, at time
// timeS: x is taken into the frame of the shape at rest (eq. 33) and measured there, and the normal turned back into
// the world.
float colliderDistance(ColliderParams c, vec3 x, float timeS, out vec3 normal) {
  vec3 restNormal;
  float distanceM = colliderRestDistance(c, colliderRestPoint(c, x, timeS), restNormal);
  normal = colliderWorldDirection(c, restNormal, timeS);
  return distanceM;
}

#ifdef FIRN_HAS_RIGID_BODIES
// Adds an impulse (kg·m/s) and its moment about the centre of mass (kg·m²/s) to the sums of the body of entry i,
// in 64-bit fixed point, so that the sums, like P2G's, do not depend on the order of the additions.
void addToRigidBody(uint i, vec3 impulseKgMPerS, vec3 momentKgM2PerS) {
  if (!countedHere) return;
  float unitsPerKgMPerS = ldexp(1.0, fixedPointFractionBits) * momentumUnitsPerKgMPerS;
  uvec4 low;
  ivec4 high;
  splitFixed64(vec4(round(impulseKgMPerS * unitsPerKgMPerS), 0.0), low, high);
  FIRN_ADD_FIXED64(colliders[i].impulseLow, colliders[i].impulseHigh, low, high)
  splitFixed64(vec4(round(momentKgM2PerS * (unitsPerKgMPerS * cellsPerM)), 0.0), low, high);
  FIRN_ADD_FIXED64(colliders[i].angularLow, colliders[i].angularHigh, low, high)
}

// Newton's third law at a node or a particle at x (docs/algorithm.md, eq. 35): the body of entry i takes the
// opposite of the impulse its response gave the snow there, and that impulse's moment about its centre of mass,
// summed in 64-bit fixed point so that the sums, like P2G's, do not depend on the order of the additions.
void pushRigidBody(uint i, vec3 x, float timeS, vec3 impulseOnSnowKgMPerS) {
  addToRigidBody(i, -impulseOnSnowKgMPerS, cross(x - colliderPivot(colliders[i], timeS), -impulseOnSnowKgMPerS));
}
#endif

// Whether the collider of entry i may hold x at timeS: it takes part (a parked body does not) and x lies within its
// reach, the sphere about its pivot that holds its whole shape (ColliderParams.contact.y). Most nodes and
// particles lie beyond every collider's reach: this reads four vec4s of the entry, where the distance reads it all
// and turns x twice by quaternions (a mesh also reads eight samples).
// `marginM` further: the points within that distance of its surface (0: of its solid).
bool colliderWithinReach(uint i, vec3 x, float timeS, float marginM) {
  if (colliders[i].shapeBoundary.w == 0) return false;
  vec4 pivotTime = colliders[i].pivotTime;
  vec3 fromPivot = x - (pivotTime.xyz + colliders[i].velocity.xyz * (timeS - pivotTime.w));
  float reachM = colliders[i].contact.y;
  return reachM < 0.0 || dot(fromPivot, fromPivot) <= (reachM + marginM) * (reachM + marginM);
}
bool colliderWithinReach(uint i, vec3 x, float timeS) { return colliderWithinReach(i, x, timeS, 0.0); }

// Velocity after meeting a boundary whose surface moves at boundaryVelocity (Stomakhin 2013 §8):
// sticky takes the boundary's velocity; slip removes the normal part of the relative velocity; separate
// does so only when approaching. Coulomb friction μ shortens the tangential part by μ·|v_n|.
vec3 boundaryResponse(vec3 v, vec3 normal, vec3 boundaryVelocity, float friction, int boundary) {
  if (boundary == BOUNDARY_STICKY) return boundaryVelocity;
  vec3 relative = v - boundaryVelocity;
  float normalSpeed = dot(relative, normal);
  if (boundary == BOUNDARY_SEPARATE && normalSpeed >= 0.0) return v;
  vec3 tangential = relative - normalSpeed * normal;
  if (normalSpeed < 0.0) {
    float tangentialSpeed = length(tangential);
    float frictionLoss = -friction * normalSpeed;
    tangential = tangentialSpeed <= frictionLoss ? vec3(0.0) : tangential * (1.0 - frictionLoss / tangentialSpeed);
  }
  return tangential + boundaryVelocity;
}

// An impulse `impulseKgMPerS` the collider of entry i gave the snow at a point of its surface moving at
// `surfaceVelocity`: the collider's work with it is the impulse times the surface's velocity (in the frame of the
// surface a response only removes energy: docs/numerics.md, The energy audit). Both go to its load where bodies.csv
// follows it (gpu::ObjectLoad), and the work is returned as work from outside the snow unless it is a rigid body's: a
// body takes the impulse back, and its own energy is audited.
float colliderImpulse(uint i, ColliderParams c, vec3 impulseKgMPerS, vec3 surfaceVelocity) {
  float workJ = dot(impulseKgMPerS, surfaceVelocity);
  if (c.contact.z != 0.0) addObjectLoad(i, impulseKgMPerS, workJ);
  return c.shapeBoundary.z != 0 ? 0.0 : workJ;
}

// Applies every collider of the entries [first, end) whose solid contains `probe` (a node, or a particle's predicted
// position) to its velocity; a rigid body takes the opposite of the change in the probe's momentum (`massKg` times
// the change in v). Adds the work the moving colliders did to `workJ`.
vec3 collideWithEntries(uint first, uint end, vec3 probe, vec3 v, float timeS, float massKg, inout float workJ) {
#ifdef FIRN_HAS_COLLIDERS
  for (uint i = first; i < end; ++i) {
    if (!colliderWithinReach(i, probe, timeS)) continue;
    ColliderParams c = colliders[i];
    vec3 normal;
    if (colliderDistance(c, probe, timeS, normal) <= 0.0) {
      vec3 surfaceVelocity = colliderVelocity(c, probe, timeS);
      vec3 response = boundaryResponse(v, normal, surfaceVelocity, c.contact.x, c.shapeBoundary.y);
#ifdef FIRN_HAS_RIGID_BODIES
      if (c.shapeBoundary.z != 0 && response != v) pushRigidBody(i, probe, timeS, massKg * (response - v));
#endif
      if (response != v) workJ += colliderImpulse(i, c, massKg * (response - v), surfaceVelocity);
      v = response;
    }
  }
#endif
  return v;
}
// Every collider of the table, the scene's and the bodies'.
vec3 collideWithColliders(vec3 probe, vec3 v, float timeS, float massKg, inout float workJ) {
  return collideWithEntries(0u, colliderCount, probe, v, timeS, massKg, workJ);
}

#ifdef FIRN_SEMI_IMPLICIT
#ifdef FIRN_HAS_RIGID_BODIES
// Body b (its index among the bodies) takes the opposite of an impulse its response gave the node at x, which goes to
// its load too.
void pushBodyAtNode(int b, vec3 x, float timeS, vec3 impulseKgMPerS) {
  if (impulseKgMPerS == vec3(0.0)) return;
  uint i = colliderCount - rigidBodyCount + uint(b);
  pushRigidBody(i, x, timeS, impulseKgMPerS);
  colliderImpulse(i, colliders[i], impulseKgMPerS, colliderVelocity(colliders[i], x, timeS));
}
#endif

// The colliders' response to a node's v*, for the semi-implicit solve (common/solver.glsl), without friction: a
// sticky collider holds all of v, a slip one the component along its normal, a separating one that component only
// while approaching; two colliders holding different normals hold it all. Friction waits for the solve
// (collidersFrictionAfterSolve): the normal impulse it is bounded by is the approach removed here and the push the
// held component takes in the solve, which v* alone cannot tell — v* carries the explicit elastic force, up to
// (c Δt / h)² times too large beyond the explicit bound, and Coulomb friction on it stopped or even reversed a
// landing body's slide. Returns SolverNode.constraint (the normal held, and the CONSTRAINT_* bits); `approachMPerS`
// is the normal speed into the colliders that the response removed. A rigid body takes the opposite of the change in
// the node's momentum (`massKg` times the change in v), as collideWithColliders gives it — except where it alone
// holds the node: then the node may be one of the body's unknowns in the solve (common/solver_bodies.glsl), and its
// index among the bodies (`soleBody`, else −1) and the impulse its response gave the node (`soleBodyImpulseKgMPerS`)
// are returned for the grid update to decide (the domain walls may hold the node too: pushBodyAtNode then). The
// moving colliders' work is added to `workJ`.
vec4 collideForSolve(vec3 probe, inout vec3 v, float timeS, float massKg, out float approachMPerS, inout float workJ,
                     out int soleBody, out vec3 soleBodyImpulseKgMPerS) {
  int code = 0;
  int holders = 0;
  vec3 heldNormal = vec3(0.0);
  approachMPerS = 0.0;
  soleBody = -1;
  soleBodyImpulseKgMPerS = vec3(0.0);
#ifdef FIRN_HAS_COLLIDERS
  for (uint i = 0u; i < colliderCount; ++i) {
    if (!colliderWithinReach(i, probe, timeS)) continue;
    ColliderParams c = colliders[i];
    vec3 normal;
    if (colliderDistance(c, probe, timeS, normal) > 0.0) continue;
    int boundary = c.shapeBoundary.y;
    vec3 boundaryVelocity = colliderVelocity(c, probe, timeS);
    float normalSpeed = dot(v - boundaryVelocity, normal);
    bool holds = true;
    if (boundary == BOUNDARY_STICKY) {
      code |= CONSTRAINT_FIXED;
    } else if (boundary == BOUNDARY_SLIP || normalSpeed < 0.0) {
      if ((code & CONSTRAINT_NORMAL) != 0 && heldNormal != normal) code |= CONSTRAINT_FIXED;
      code |= CONSTRAINT_NORMAL;
      heldNormal = normal;
      approachMPerS = max(-normalSpeed, 0.0);
    } else {
      holds = false;
    }
    vec3 response = boundaryResponse(v, normal, boundaryVelocity, 0.0, boundary);
#ifdef FIRN_HAS_RIGID_BODIES
    if (c.shapeBoundary.z != 0 && holds && holders == 0) {
      soleBody = int(i - (colliderCount - rigidBodyCount));  // its push waits for the grid update's decision
      soleBodyImpulseKgMPerS = massKg * (response - v);
      v = response;
      ++holders;
      continue;
    }
    if (c.shapeBoundary.z != 0 && response != v) pushRigidBody(i, probe, timeS, massKg * (response - v));
#endif
    if (response != v) workJ += colliderImpulse(i, c, massKg * (response - v), boundaryVelocity);
    v = response;
    if (holds) ++holders;
  }
#ifdef FIRN_HAS_RIGID_BODIES
  if (soleBody >= 0 && holders > 1) {
    pushBodyAtNode(soleBody, probe, timeS, soleBodyImpulseKgMPerS);  // not the body's alone
    soleBody = -1;
  }
#endif
#endif
  return vec4(heldNormal, float(code));
}

// Coulomb friction after the solve at a node that a collider held along `constraint`'s normal: the tangential
// velocity relative to that collider shortens by μ times the collider's normal impulse over the node's mass,
// `normalImpulseMPerS` (SolverNode.residual.w), and stops at 0, so it never reverses; a pull (an impulse below 0)
// brings no friction. The held normal component is already the collider's, so the relative velocity is all
// tangential. With β = 0 this is boundaryResponse's friction to the bit, for colliders at rest. A rigid body takes the
// opposite of the friction's change in the node's momentum (`massKg` times the change in v); a moving collider's work
// is added to `workJ`.
vec3 collidersFrictionAfterSolve(vec3 probe, vec3 v, float timeS, float massKg, vec4 constraint,
                                 float normalImpulseMPerS, inout float workJ) {
#ifdef FIRN_HAS_COLLIDERS
  int code = int(constraint.w);
  if ((code & CONSTRAINT_NORMAL) == 0 || (code & CONSTRAINT_FIXED) != 0) return v;  // no collider's normal, or all held
  for (uint i = 0u; i < colliderCount; ++i) {
    if (!colliderWithinReach(i, probe, timeS)) continue;
    ColliderParams c = colliders[i];
    vec3 normal;
    if (colliderDistance(c, probe, timeS, normal) > 0.0 || normal != constraint.xyz) continue;
    vec3 boundaryVelocity = colliderVelocity(c, probe, timeS);
    vec3 tangential = v - boundaryVelocity;
    float tangentialSpeed = length(tangential);
    float frictionLoss = c.contact.x * max(normalImpulseMPerS, 0.0);
    tangential = tangentialSpeed <= frictionLoss ? vec3(0.0) : tangential * (1.0 - frictionLoss / tangentialSpeed);
    vec3 response = tangential + boundaryVelocity;
#ifdef FIRN_HAS_RIGID_BODIES
    if (c.shapeBoundary.z != 0 && response != v) pushRigidBody(i, probe, timeS, massKg * (response - v));
#endif
    if (response != v) workJ += colliderImpulse(i, c, massKg * (response - v), boundaryVelocity);
    return response;
  }
#endif
  return v;
}

#ifdef FIRN_SOLUTION_PRODUCT
// Newton's third law for the solve's constraints (docs/algorithm.md, eq. 35 in the semi-implicit step): at a node the
// constraints hold, the solution x keeps the held components of v*, and the rows the projection drops from
// (M + β Δt² H) x = M v* are the impulse λ the colliders gave the snow there, λ = (A x − M v*) on the held
// components = β Δt² (H x) on them (`heldProductKgMPerS`, the product of x less its free components). Each collider
// whose solid holds the node has its part: a sticky one all of λ, a slip or separating one the component along its
// normal, where the constraint holds that normal (a node two colliders hold whole: each one's normal component of λ).
// A rigid body takes the opposite of its part; a moving collider's part, times its surface's velocity, is its work on
// the snow, added to `workJ` (colliderImpulse). Colliders at rest do none.
void constraintsAfterSolve(vec3 probe, float timeS, vec4 constraint, vec3 heldProductKgMPerS, inout float workJ) {
  int code = int(constraint.w);
  if ((code & (CONSTRAINT_NORMAL | CONSTRAINT_FIXED)) == 0) return;  // no collider holds the node
  for (uint i = 0u; i < colliderCount; ++i) {
    // A body, a collider moving now, or one whose load bodies.csv reports (a keyframed one may rest a while).
    bool counted = colliders[i].velocity.xyz != vec3(0.0) || colliders[i].angularVelocity.xyz != vec3(0.0) ||
                   colliders[i].contact.z != 0.0;
    if (!counted || !colliderWithinReach(i, probe, timeS)) continue;
    ColliderParams c = colliders[i];
    vec3 normal;
    if (colliderDistance(c, probe, timeS, normal) > 0.0) continue;
    vec3 share;
    if (c.shapeBoundary.y == BOUNDARY_STICKY) {
      share = heldProductKgMPerS;
    } else if ((code & CONSTRAINT_FIXED) != 0 || normal == constraint.xyz) {
      share = dot(heldProductKgMPerS, normal) * normal;
    } else {
      continue;  // a separating collider the node was leaving when the grid update met it
    }
    if (share == vec3(0.0)) continue;
#ifdef FIRN_HAS_RIGID_BODIES
    if (c.shapeBoundary.z != 0) pushRigidBody(i, probe, timeS, share);
#endif
    workJ += colliderImpulse(i, c, share, colliderVelocity(c, probe, timeS));
  }
}
#endif

// The axes on which the domain walls hold a node whose velocity before their response is v: CONSTRAINT_WALL_X
// shifted by the axis.
int wallConstraint(vec3 probe, vec3 v, vec3 interiorMin, vec3 interiorMax) {
  int code = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if ((probe[axis] <= interiorMin[axis] && v[axis] < 0.0) || (probe[axis] >= interiorMax[axis] && v[axis] > 0.0)) {
      code |= CONSTRAINT_WALL_X << axis;
    }
  }
  return code;
}
#endif

// The domain's outer cells are walls: beyond `interiorMin`/`interiorMax` motion out of the domain stops
// (a frictionless separating boundary on each face).
vec3 collideWithDomainWalls(vec3 probe, vec3 v, vec3 interiorMin, vec3 interiorMax) {
  for (int axis = 0; axis < 3; ++axis) {
    if (probe[axis] <= interiorMin[axis] && v[axis] < 0.0) v[axis] = 0.0;
    if (probe[axis] >= interiorMax[axis] && v[axis] > 0.0) v[axis] = 0.0;
  }
  return v;
}

// Walls sit FIRN_WALL_CELLS cells inside the domain (GridSpec::wallCells) so every stencil stays on the grid.
const float WALL_CELLS = float(FIRN_WALL_CELLS);
vec3 interiorMin() { return gridOriginM + WALL_CELLS * cellSizeM; }
vec3 interiorMax() { return gridOriginM + (vec3(gridNodes - 1) - WALL_CELLS) * cellSizeM; }
