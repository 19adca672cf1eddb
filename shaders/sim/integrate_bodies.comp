#version 430 core
// Rigid bodies (docs/algorithm.md, Rigid bodies): an invocation per body, after G2P. The body takes the snow's push
// of this step (the impulses its entry gathered at the nodes and particles its response changed, eq. 35) — in the
// explicit step, since its coupled solve, with gravity and the images' push taken before it (predict_bodies.comp);
// in the semi-implicit step all of it, and gravity — then its contacts with the scene's colliders and the domain
// walls (eq. 36), and moves: symplectic Euler, v and L first, then x by v and the orientation by ω = I⁻¹ L (eq. 37).
// Its entry's pose, velocities and sums are rewritten for the next step.
// The energy ledger takes the work the moving colliders do on the body through its contacts, and the energy the
// explicit coupling gives it (common/energy.glsl; docs/numerics.md, The energy audit; mirror_stress.comp adds the
// images' share).
// Reads: the collider table, the contact probes (field buffer). Writes: the bodies' entries, the ledger's flows, and
// with adaptive steps the watchdog's fastest speed.
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/energy.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

// Sequential impulses over the probes in contact (Gauss–Seidel): each pass removes what the last left of the
// approach at every probe; a resting box settles within a few.
const int CONTACT_PASSES = 4;

vec3 probe(ColliderParams body, int k) {
  int first = body.bodyProbes.x + 3 * k;
  return vec3(texelFetch(colliderFields, first).r, texelFetch(colliderFields, first + 1).r,
              texelFetch(colliderFields, first + 2).r);
}

// The deepest of the scene's colliders and the domain walls at x, at timeS: φ (m) and its outward normal, and
// the velocity of that surface and its friction (a wall's 0 and at rest).
float deepestContact(vec3 x, float timeS, uint staticColliders, out vec3 normal, out vec3 surfaceVelocity) {
  float deepest = 1e30;
  normal = vec3(0.0, 1.0, 0.0);
  surfaceVelocity = vec3(0.0);
  for (uint c = 0u; c < staticColliders; ++c) {
    vec3 n;
    float distanceM = colliderDistance(colliders[c], x, timeS, n);
    if (distanceM < deepest) {
      deepest = distanceM;
      normal = n;
      surfaceVelocity = colliderVelocity(colliders[c], x, timeS);
    }
  }
  vec3 low = x - interiorMin(), high = interiorMax() - x;
  for (int axis = 0; axis < 3; ++axis) {
    if (low[axis] < deepest) {
      deepest = low[axis];
      normal = vec3(0.0);
      normal[axis] = 1.0;
      surfaceVelocity = vec3(0.0);
    }
    if (high[axis] < deepest) {
      deepest = high[axis];
      normal = vec3(0.0);
      normal[axis] = -1.0;
      surfaceVelocity = vec3(0.0);
    }
  }
  return deepest;
}

void main() {
  uint b = gl_GlobalInvocationID.x;
  if (b >= rigidBodyCount) return;
  uint staticColliders = colliderCount - rigidBodyCount;
  uint i = staticColliders + b;
  ColliderParams body = colliders[i];
  if (body.shapeBoundary.w == 0) return;  // parked
  float massKg = body.bodyMass.x;
  float probeRadiusM = body.bodyMass.y;
  float friction = body.velocityFriction.w;
  vec3 x = colliderPivot(body, timeS);
  vec4 q = body.rotation;
  mat3 turn = rotationMatrix(q);
  mat3 inverseInertia = worldInverseInertia(body, turn);
  vec3 impulse, angularImpulse;
  summedPush(body, impulse, angularImpulse);
#ifdef FIRN_SEMI_IMPLICIT
  // The snow's push (eq. 35) and gravity. The snow met the body's surface moving as it moved before the push, which
  // the body takes only now: the push's own energy is what this explicit coupling adds to the snow's and the body's.
  vec3 v = body.velocityFriction.xyz + impulse / massKg + dtS * gravityMPerS2;
  vec3 angularMomentum = body.angularMomentum.xyz + angularImpulse;
  float couplingJ = pushOwnEnergyJ(massKg, inverseInertia, impulse, angularImpulse);
#else
  // The snow's impulses since the coupled solve (eq. 39), added to the body's velocities before it (V*, L*:
  // predict_bodies.comp): the solve's own at the nodes it held, which take the body to the solved (V', ω') its entry
  // moves at now, and the rest — friction, the particles G2P met — which the snow gave at the surface moving at
  // (V', ω'): their energy beyond that is the departure's own, ½ M |V − V'|² + ½ (ω − ω') · I (ω − ω').
  vec3 v = body.freeVelocity.xyz + impulse / massKg;
  vec3 angularMomentum = body.angularMomentum.xyz + angularImpulse;
  vec3 departure = v - body.velocityFriction.xyz;
  vec3 turnDeparture = inverseInertia * angularMomentum - body.angularVelocity.xyz;
  float couplingJ = 0.5 * massKg * dot(departure, departure) +
                    0.5 * dot(turnDeparture, inverse(inverseInertia) * turnDeparture);
#endif
  vec3 omega = inverseInertia * angularMomentum;
  float workJ = 0.0;  // of the moving colliders through the contacts

  // Contacts (eq. 36): at each probe the end of the step would carry into a collider or a wall, the impulse that
  // stops its approach, j_n = −u_n / (1/m + n · (I⁻¹ (r × n)) × r), and Coulomb friction up to μ j_n against the
  // tangential slip.
  float endTimeS = timeS + dtS;
  for (int pass = 0; pass < CONTACT_PASSES; ++pass) {
    for (int k = 0; k < body.bodyProbes.y; ++k) {
      vec3 r = turn * probe(body, k);
      vec3 normal, surfaceVelocity;
      float distanceM = deepestContact(x + dtS * v + r, endTimeS, staticColliders, normal, surfaceVelocity) -
                        probeRadiusM;
      if (distanceM >= 0.0) continue;
      vec3 contactR = r - probeRadiusM * normal;
      vec3 relative = v + cross(omega, contactR) - surfaceVelocity;
      float approach = dot(relative, normal);
      if (approach >= 0.0) continue;
      float normalMass = 1.0 / massKg + dot(normal, cross(inverseInertia * cross(contactR, normal), contactR));
      float normalImpulse = -approach / normalMass;
      vec3 contactImpulse = normalImpulse * normal;
      vec3 slip = relative - approach * normal;
      float slipSpeed = length(slip);
      if (slipSpeed > 0.0) {
        vec3 t = slip / slipSpeed;
        float tangentMass = 1.0 / massKg + dot(t, cross(inverseInertia * cross(contactR, t), contactR));
        contactImpulse -= min(slipSpeed / tangentMass, friction * normalImpulse) * t;
      }
      v += contactImpulse / massKg;
      angularMomentum += cross(contactR, contactImpulse);
      workJ += dot(contactImpulse, surfaceVelocity);
      omega = inverseInertia * angularMomentum;
    }
  }

  // Symplectic Euler (eq. 37), then out of whatever solid a probe still ends in, along its normal.
  x += dtS * v;
  q = normalize(composeTurns(q, turnOver(omega, dtS)));
  turn = rotationMatrix(q);
  for (int k = 0; k < body.bodyProbes.y; ++k) {
    vec3 normal, surfaceVelocity;
    float distanceM = deepestContact(x + turn * probe(body, k), endTimeS, staticColliders, normal, surfaceVelocity) -
                      probeRadiusM;
    if (distanceM < 0.0) x -= distanceM * normal;
  }
  inverseInertia = worldInverseInertia(body, turn);

  colliders[i].pivotTime = vec4(x, endTimeS);
  colliders[i].rotation = q;
  colliders[i].velocityFriction.xyz = v;
  colliders[i].angularVelocity.xyz = inverseInertia * angularMomentum;
  colliders[i].angularMomentum.xyz = angularMomentum;
  clearPush(i);
  addEnergyFlows(vec4(workJ, 0.0, couplingJ, 0.0));
#ifdef FIRN_ADAPTIVE_DT
  // The next step must keep the body's surface within a cell too, as g2p.comp keeps the particles: its fastest point
  // moves at |v| + |ω| r, r its reach from the centre of mass (ColliderParams.angularVelocity.w).
  reportSpeed(length(v) + length(colliders[i].angularVelocity.xyz) * colliders[i].angularVelocity.w);
#endif
}
