// The contacts of rigid bodies with the scene's colliders, the walls and each other (docs/algorithm.md, eq. 36), as
// the passes over all the bodies at once resolve them: at contact probes in each body's frame, by sequential impulses
// with accumulated totals (integrate_bodies.comp; meet_bodies.comp, for the bodies' contacts with each other within
// the explicit step's coupled solve and after the semi-implicit solve).
#include "common/body_blocks.glsl"

// Sequential impulses over the probes in contact (Gauss–Seidel): each pass removes what the last left of the
// approach at every probe; a resting box settles within a few.
const int CONTACT_PASSES = 10;

// Probe k of the body of entry i, in its own frame (m).
vec3 probe(uint i, int k) { return fieldVector(bodyRecords[bodyOf(i)].probes.x + 3 * k); }

// The inverse of the effective mass a body of mass M and world inverse inertia I⁻¹ has along direction d at r from its
// centre of mass: 1/M + d · (I⁻¹ (r × d)) × r.
float inverseEffectiveMass(float massKg, mat3 inverseInertia, vec3 r, vec3 d) {
  return 1.0 / massKg + dot(d, cross(inverseInertia * cross(r, d), r));
}

// The impulses the contacts have given this step, one slot per probe and what it may meet (the colliders and walls,
// then each other body), numbered in the order the passes visit them: xyz the friction, w the normal impulse. Each
// pass adds to a slot what makes its contact's approach zero and keeps its total within the contact's laws — the
// normal total ≥ 0, the friction's within μ of it — so that a later pass can take back what an earlier one gave too
// much (projected Gauss–Seidel with accumulated impulses, Catto 2005): a box landing flat on its 26 probes is not
// turned by the first probe's taking the whole landing. A contact beyond the slots (CONTACT_SLOTS) starts each pass
// from nothing.
vec4 accumulated[CONTACT_SLOTS];

// A friction impulse within Coulomb's cone: at most μ times the normal impulse, `limit`.
vec3 withinFrictionCone(vec3 friction, float limit) {
  return length(friction) > limit ? friction * (limit / length(friction)) : friction;
}

// The impulse this pass adds at contact `slot` on a body whose velocity relative to what it meets there is
// `relative`, along the outward `normal` of what it meets: perfectly inelastic with Coulomb friction μ (eq. 36), given
// the contact's inverse effective masses along the normal and along the slip's direction t (both bodies' summed, where
// it meets another body).
vec3 contactImpulse(int slot, vec3 relative, vec3 normal, float friction, float normalInverseMass,
                    float tangentInverseMass, vec3 t) {
  float approach = dot(relative, normal);
  vec3 slip = relative - approach * normal;
  vec3 frictionWanted = -length(slip) / tangentInverseMass * t;
  vec4 before = slot < CONTACT_SLOTS ? accumulated[slot] : vec4(0.0);
  float normalTotal = max(before.w - approach / normalInverseMass, 0.0);
  vec3 frictionTotal = before.xyz + frictionWanted;
  frictionTotal = withinFrictionCone(frictionTotal, friction * normalTotal);
  if (slot < CONTACT_SLOTS) accumulated[slot] = vec4(frictionTotal, normalTotal);
  return (normalTotal - before.w) * normal + (frictionTotal - before.xyz);
}

// The direction of the tangential slip of a relative velocity, or 0 where there is none.
vec3 slipDirection(vec3 relative, vec3 normal) {
  vec3 slip = relative - dot(relative, normal) * normal;
  return length(slip) > 0.0 ? normalize(slip) : vec3(0.0);
}

bool takesPart(uint i) { return colliders[i].shapeBoundary.w != 0; }  // a parked body does not

// A probe of a body, r from its centre of mass and at `end` at the step's end, against body entry o there: whether it
// lies within o's solid (less the probe's radius), and if so o's outward normal, the contact point's place from each
// centre of mass and the velocity there of the body, moving at v and ω, relative to o's surface.
bool meetsBody(uint o, vec3 r, vec3 end, float endTimeS, float probeRadiusM, vec3 v, vec3 omega, out vec3 normal,
               out vec3 contactR, out vec3 otherR, out vec3 relative) {
  if (!colliderWithinReach(o, end, endTimeS, probeRadiusM)) return false;
  ColliderParams other = colliders[o];
  if (colliderDistance(other, end, endTimeS, normal) - probeRadiusM >= 0.0) return false;
  contactR = r - probeRadiusM * normal;
  vec3 point = end - probeRadiusM * normal;
  otherR = point - colliderPivot(other, endTimeS);
  relative = v + cross(omega, contactR) - colliderVelocity(other, point, endTimeS);
  return true;
}

// Two bodies' friction where they meet: the geometric mean of theirs.
float meetingFriction(uint i, uint o) {
  return sqrt(colliders[i].contact.x * colliders[o].contact.x);
}

#ifdef FIRN_SEMI_IMPLICIT
// The semi-implicit step's warm start (docs/algorithm.md, Rigid bodies in the semi-implicit step). Its bodies meet
// each other after the solve (meet_bodies.comp), so a body resting on another that holds nodes in the solve would pass
// its weight on to the snow under that one a step late, every step, as a kick after the solve, and a stack would sink
// and rock. Each contact's impulse of the last step (BodyContact, kept in the bodies' records from step to step) is
// given to both bodies before the solve (predict_bodies.comp), which carries it into the snow with gravity; the
// contacts after the solve start from it and revise it (Catto 2005's warm starting, with the accumulated impulses of
// eq. 36). The contacts beyond CONTACT_SLOTS (a slot for each probe and other body) start from nothing, as each pass's
// do.

// Whether slot s holds a contact of the last step of two bodies that both take part.
bool slotInUse(int s) {
  ivec4 key = bodyContacts[s].key;
  return key.w != 0 && takesPart(uint(key.x)) && takesPart(uint(key.z));
}

// Slot s's impulse on its first body (kg·m/s; the other takes the opposite), and where it acts from each body's centre
// of mass as the step starts (the poses integrate_bodies.comp left, which every pass of the step reads alike): the
// first body's probe, less its radius along the normal, and that point from the other's centre.
vec3 slotImpulse(int s, out vec3 r, out vec3 otherR) {
  BodyContact contact = bodyContacts[s];
  uint i = uint(contact.key.x);
  ColliderParams body = colliders[i];
  float probeRadiusM = bodyRecords[bodyOf(i)].massRadius.y;
  r = rotationMatrix(body.rotation) * probe(i, contact.key.y) - probeRadiusM * contact.normal.xyz;
  otherR = body.pivotTime.xyz + r - colliders[contact.key.z].pivotTime.xyz;
  return contact.impulse.w * contact.normal.xyz + contact.impulse.xyz;
}

// What body entry e takes from the slots' impulses before the solve (kg·m/s), and their moment about its centre of
// mass (kg·m²/s).
void impulsesBeforeSolve(uint e, out vec3 impulse, out vec3 moment) {
  impulse = vec3(0.0);
  moment = vec3(0.0);
  for (int s = 0; s < CONTACT_SLOTS; ++s) {
    if (!slotInUse(s)) continue;
    ivec4 key = bodyContacts[s].key;
    if (uint(key.x) != e && uint(key.z) != e) continue;
    vec3 r, otherR;
    vec3 j = slotImpulse(s, r, otherR);
    if (uint(key.z) == e) {  // the other body: the opposite, at its own arm
      j = -j;
      r = otherR;
    }
    impulse += j;
    moment += cross(r, j);
  }
}

// The slot meet_bodies.comp gives the contact of body entry i's probe k with body entry o: for each body that takes
// part, in the table's order, each of its probes has one for each other body that takes part.
int contactSlotOf(uint i, int k, uint o) {
  int others = -1;
  for (uint b = bodyEntry(0); b < colliderCount; ++b) others += takesPart(b) ? 1 : 0;
  int slot = 0;
  for (uint b = bodyEntry(0); b < i; ++b) slot += takesPart(b) ? bodyRecords[bodyOf(b)].probes.y * others : 0;
  slot += k * others;
  for (uint b = bodyEntry(0); b < o; ++b) slot += b != i && takesPart(b) ? 1 : 0;
  return slot;
}
#endif
