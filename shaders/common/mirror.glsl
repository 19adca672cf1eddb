// Which particles' stress is mirrored into a rigid body (docs/algorithm.md eq. 38): those within a kernel's reach
// of its surface, outside it. list_mirrored.comp lists them, mirror_stress.comp scatters their images.

// The kernel's reach: a particle farther from the surface than this has no image node outside the body.
float mirrorReachM() { return 0.5 * float(KERNEL_WIDTH) * cellSizeM; }

// The signed distance of x from the surface of the collider table's entry i, and the outward normal there, if it is
// a rigid body that takes part and x lies within reachM of its reach; a large distance (nothing mirrored) else.
float mirroredDistance(uint i, vec3 x, float reachM, out vec3 normal) {
  normal = vec3(0.0);
  if (colliders[i].shapeBoundary.z == 0 || !colliderWithinReach(i, x, timeS, reachM)) return 2.0 * reachM;
  return colliderDistance(colliders[i], x, timeS, normal);
}
