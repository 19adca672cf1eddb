#version 430 core
// Rigid bodies (docs/algorithm.md, Rigid bodies): one invocation for every body, after G2P. Each body takes the snow's
// push of this step (the impulses its entry gathered at the nodes and particles its response changed, eq. 35) since its
// solve with the nodes it holds, with gravity and the images' push taken before it (predict_bodies.comp). Then the
// bodies' contacts with the scene's colliders, the domain walls and each other (eq. 36), and each moves: symplectic
// Euler, v and L first, then x by v and the orientation by ω = I⁻¹ L (eq. 37). Their entries' pose, velocities and
// sums, and L in their records, are rewritten for the next step. One invocation, so that a contact between two bodies
// changes both at once and the impulses run in one order on every run. The energy ledger takes the work the moving
// colliders do on the bodies through their contacts, and the energy the explicit coupling gives them
// (common/energy.glsl; docs/numerics.md, The energy audit; mirror_stress.comp adds the images' share). The bodies'
// contact probes come from the field buffer, a buffer texture (no storage buffer).
// Reads: colliders (the table and the bodies' entries with their sums), watchdog (the ledger's atomics' old values),
//        bodies (the records' dynamics; semi-implicit step: velocity[0].w).
// Writes: colliders (the bodies' entries: pose and velocities and their sums cleared), bodies (angular momentum),
//         watchdog (the ledger's flows and with adaptive steps the fastest speed).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/body_contacts.glsl"
#include "common/energy.glsl"

layout(local_size_x = 1) in;

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

// The velocities of the body of entry i as its entry and record hold them during the contacts: V, and L with
// ω = I⁻¹ L.
void setVelocities(uint i, vec3 v, vec3 angularMomentum, mat3 inverseInertia) {
  colliders[i].velocity.xyz = v;
  bodyRecords[bodyOf(i)].angularMomentum.xyz = angularMomentum;
  colliders[i].angularVelocity.xyz = inverseInertia * angularMomentum;
}

void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  countedHere = bodiesCountedElsewhere == 0u;
  uint staticColliders = colliderCount - rigidBodyCount;
  float workJ = 0.0;      // of the moving colliders through the contacts
  float couplingJ = 0.0;  // the explicit coupling's own energy

  // The snow's push since the bodies' solve.
  for (uint i = staticColliders; i < colliderCount; ++i) {
    if (!takesPart(i)) continue;
    ColliderParams body = colliders[i];
    int b = bodyOf(i);
    float massKg = bodyRecords[b].massRadius.x;
    mat3 inverseInertia = worldInverseInertia(b, rotationMatrix(body.rotation));
    vec3 impulse, angularImpulse;
    summedPush(body, impulse, angularImpulse);
    // The snow's impulses since the bodies' solve with the nodes they hold (the explicit step's coupled solve, eq. 39;
    // the semi-implicit step's, eq. 39a), added to the body's velocities before it (V*, L*: predict_bodies.comp, or
    // the solve's own where it gave them: solver_bodies_finish.comp): the explicit solve's own at the nodes it held,
    // which take the body to the solved (V', ω') its entry moves at now, and the rest — friction, the particles G2P
    // met — which the snow gave at the surface moving at (V', ω'): their energy beyond that is the departure's own,
    // ½ M |V − V'|² + ½ (ω − ω') · I (ω − ω').
    vec3 v = bodyRecords[b].freeVelocity.xyz + impulse / massKg;
    vec3 angularMomentum = bodyRecords[b].angularMomentum.xyz + angularImpulse;
    vec3 departure = v - body.velocity.xyz;
    vec3 turnDeparture = inverseInertia * angularMomentum - body.angularVelocity.xyz;
    couplingJ += 0.5 * massKg * dot(departure, departure) +
                 0.5 * dot(turnDeparture, inverse(inverseInertia) * turnDeparture);
    setVelocities(i, v, angularMomentum, inverseInertia);
  }

  // Contacts (eq. 36): at each probe the end of the step would carry into a collider, a wall or another body, the
  // impulse that stops its approach, j_n = −u_n / k_n, and Coulomb friction up to μ j_n against the tangential slip,
  // k the inverse effective mass along each direction: 1/M + n · (I⁻¹ (r × n)) × r, and the other body's beside it.
  // Another body is met where it will be at the step's end (its entry moves by its V and ω from now), and takes the
  // opposite impulse; two bodies' friction is the geometric mean of theirs.
  float endTimeS = timeS + dtS;
  for (int slot = 0; slot < CONTACT_SLOTS; ++slot) accumulated[slot] = vec4(0.0);
  for (int pass = 0; pass < CONTACT_PASSES; ++pass) {
    int contactSlot = 0;
    for (uint i = staticColliders; i < colliderCount; ++i) {
      if (!takesPart(i)) continue;
      ColliderParams body = colliders[i];
      int b = bodyOf(i);
      float massKg = bodyRecords[b].massRadius.x;
      float probeRadiusM = bodyRecords[b].massRadius.y;
      vec3 x = colliderPivot(body, timeS);
      mat3 turn = rotationMatrix(body.rotation);
      mat3 inverseInertia = worldInverseInertia(b, turn);
      vec3 v = body.velocity.xyz;
      vec3 angularMomentum = bodyRecords[b].angularMomentum.xyz;
      vec3 omega = body.angularVelocity.xyz;
      for (int k = 0; k < bodyRecords[b].probes.y; ++k) {
        vec3 r = turn * probe(i, k);
        vec3 end = x + dtS * v + r;
        vec3 normal, surfaceVelocity;
        float distanceM = deepestContact(end, endTimeS, staticColliders, normal, surfaceVelocity) - probeRadiusM;
        int slot = contactSlot++;
        if (distanceM < 0.0) {
          vec3 contactR = r - probeRadiusM * normal;
          vec3 relative = v + cross(omega, contactR) - surfaceVelocity;
          vec3 t = slipDirection(relative, normal);
          vec3 j = contactImpulse(slot, relative, normal, body.contact.x,
                                  inverseEffectiveMass(massKg, inverseInertia, contactR, normal),
                                  inverseEffectiveMass(massKg, inverseInertia, contactR, t), t);
          v += j / massKg;
          angularMomentum += cross(contactR, j);
          workJ += dot(j, surfaceVelocity);
          omega = inverseInertia * angularMomentum;
        }
        for (uint o = staticColliders; o < colliderCount; ++o) {
          if (o == i || !takesPart(o)) continue;
          slot = contactSlot++;
#ifdef FIRN_SEMI_IMPLICIT
          // Met after the solve where one of the two held nodes in it and the other none (meet_bodies.comp).
          if (holdsNodes(b) != holdsNodes(bodyOf(o))) continue;
#endif
          vec3 contactR, otherR, relative;
          if (!meetsBody(o, r, end, endTimeS, probeRadiusM, v, omega, normal, contactR, otherR, relative)) continue;
          ColliderParams other = colliders[o];
          int a = bodyOf(o);
          vec3 t = slipDirection(relative, normal);
          float otherMassKg = bodyRecords[a].massRadius.x;
          mat3 otherInverseInertia = worldInverseInertia(a, rotationMatrix(other.rotation));
          vec3 j = contactImpulse(slot, relative, normal, meetingFriction(i, o),
                                  inverseEffectiveMass(massKg, inverseInertia, contactR, normal) +
                                      inverseEffectiveMass(otherMassKg, otherInverseInertia, otherR, normal),
                                  inverseEffectiveMass(massKg, inverseInertia, contactR, t) +
                                      inverseEffectiveMass(otherMassKg, otherInverseInertia, otherR, t),
                                  t);
          v += j / massKg;
          angularMomentum += cross(contactR, j);
          omega = inverseInertia * angularMomentum;
          setVelocities(o, other.velocity.xyz - j / otherMassKg,
                        bodyRecords[a].angularMomentum.xyz - cross(otherR, j), otherInverseInertia);
        }
      }
      setVelocities(i, v, angularMomentum, inverseInertia);
    }
  }

  // Symplectic Euler (eq. 37), then out of whatever collider or wall a probe still ends in, along its normal.
  for (uint i = staticColliders; i < colliderCount; ++i) {
    if (!takesPart(i)) continue;
    ColliderParams body = colliders[i];
    int b = bodyOf(i);
    float probeRadiusM = bodyRecords[b].massRadius.y;
    vec3 v = body.velocity.xyz;
    vec3 angularMomentum = bodyRecords[b].angularMomentum.xyz;
    vec3 x = colliderPivot(body, timeS) + dtS * v;
    vec4 q = normalize(composeTurns(body.rotation, turnOver(body.angularVelocity.xyz, dtS)));
    mat3 turn = rotationMatrix(q);
    for (int k = 0; k < bodyRecords[b].probes.y; ++k) {
      vec3 normal, surfaceVelocity;
      float distanceM = deepestContact(x + turn * probe(i, k), endTimeS, staticColliders, normal,
                                       surfaceVelocity) - probeRadiusM;
      if (distanceM < 0.0) x -= distanceM * normal;
    }
    mat3 inverseInertia = worldInverseInertia(b, turn);
    colliders[i].pivotTime = vec4(x, endTimeS);
    colliders[i].rotation = q;
    colliders[i].angularVelocity.xyz = inverseInertia * angularMomentum;
    clearPush(i);
#ifdef FIRN_ADAPTIVE_DT
    // The next step must keep the body's surface within a cell too, as g2p.comp keeps the particles: its fastest
    // point moves at |v| + |ω| r, r its reach from the centre of mass (ColliderParams.contact.y).
    reportSpeed(length(v) + length(colliders[i].angularVelocity.xyz) * colliders[i].contact.y);
#endif
  }
  addEnergyFlows(vec4(workJ, 0.0, couplingJ, 0.0));
}
