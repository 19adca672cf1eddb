// Which particles' stress is mirrored into a rigid body (docs/algorithm.md eq. 38): those within a kernel's reach
// of its surface, outside it. list_mirrored.comp lists them, mirror_stress.comp scatters their images.

// Whether particle p's stress is mirrored at all: a fluid's (water) only. A fluid has no shear stiffness to carry a
// body through the nodes the body holds, which pass on χ_s < 1 of its pressure, so a floating body takes Archimedes'
// force from its images; a solid (snow, sand, the elastic models) deforms until the held nodes carry the body, and an
// image, a push as stiff as the solid applied explicitly, only bounds the step: a 1.2 kg box and one of 0.12 kg on a
// bed of snow came apart at 0.9 of the bed's elastic bound with their images and rest there without them
// (docs/algorithm.md, The snow's stress mirrored into the body).
#ifndef FIRN_WITHOUT_PARTICLE_BUFFERS
bool stressMirrored(uint p) { return materials[plasticState[p].materialIndex].model.x == MODEL_WATER; }
#endif

// The kernel's reach: a particle farther from the surface than this has no image node outside the body.
float mirrorReachM() { return 0.5 * float(KERNEL_WIDTH) * cellSizeM; }

// Whether the collider table's entry i is a rigid body that takes part and x lies within marginM of its reach.
bool bodyWithinReach(uint i, vec3 x, float marginM) {
  return colliders[i].shapeBoundary.z != 0 && colliderWithinReach(i, x, timeS, marginM);
}

// The signed distance of x from the surface of the collider table's entry i, and the outward normal there, if it is
// a rigid body that takes part and x lies within reachM of its reach; a large distance (nothing mirrored) else.
float mirroredDistance(uint i, vec3 x, float reachM, out vec3 normal) {
  normal = vec3(0.0);
  if (!bodyWithinReach(i, x, reachM)) return 2.0 * reachM;
  return colliderDistance(colliders[i], x, timeS, normal);
}

// How steeply a collider's φ may change, |φ(x) − φ(y)| ≤ slope |x − y|: 1 for the analytic shapes, whose φ is a
// distance. A mesh's field is interpolated trilinearly, as steep as shapeA.w within its lattice (the host's bound
// from the samples), and beyond the lattice grows by the distance from it: a move splits per axis into one along the
// lattice and one away from it, so the slope is at most √(w² + 1).
float colliderSlope(ColliderParams c) {
  return c.shapeBoundary.x == SHAPE_MESH ? sqrt(c.shapeA.w * c.shapeA.w + 1.0) : 1.0;
}

// Whether a particle within radiusM of `centreM` may lie within reachM of rigid body i's surface, outside it (the
// test list_mirrored.comp makes, for every point of that ball at once): φ at the centre, give or take the slope
// times the radius, or beyond the body's reach.
bool mayHoldMirrored(uint i, vec3 centreM, float radiusM, float reachM) {
  if (!bodyWithinReach(i, centreM, radiusM + reachM)) return false;
  vec3 normal;
  float distanceM = colliderDistance(colliders[i], centreM, timeS, normal);
  float spreadM = colliderSlope(colliders[i]) * radiusM;
  return distanceM - spreadM < reachM && distanceM + spreadM > 0.0;
}
