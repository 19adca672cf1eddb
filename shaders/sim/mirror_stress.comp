#version 430 core
// The stress at a rigid body's surface, mirrored into it (docs/algorithm.md, Rigid bodies, eq. 38): after P2G, an
// invocation per particle that list_mirrored.comp listed, those within a kernel's reach of a body's surface
// (0 < φ < reach). Each has a mirror image x' = x − 2 φ n inside the body, with its volume and its stress reflected
// across the surface, R τ R with R = I − 2 n nᵀ. The image's contributions −Δt V0 R τ R ∇w_i(x') to the nodes outside
// the body that hold snow are added to them as P2G adds its impulses, and their opposite goes to the body
// (addToRigidBody): the contributions of an image sum to zero over its stencil (Σ_i ∇w_i = 0), so the ones inside
// the body, which are the body's, are that opposite, and momentum is kept exactly. (Adding the inside ones to their
// nodes instead, for the grid update to pass on, would leave a slip or separating body's tangential share in nodes
// of almost no mass.) Without the images the nodes a body holds see the kernel's transition χ = Σ_{i held} w_i only
// where the snow is, outside the surface, and pass on χ_s < 1 of the snow's traction.
// Dispatched to push, and to measure (measuringWork) the energy the pushes give the nodes at the nodes' sums as no
// push is changing them, which reads the same whatever the order of the pushes' invocations: half before the pushes
// and half after (RigidBodies::afterTransfer). Explicit steps only: the semi-implicit step's bodies are unknowns of its
// solve, and an explicit push as stiff as the snow would bound its step (docs/algorithm.md).
// Reads: blockTable (mirrorDispatch: the dispatch record and w), particleRanks (the list), positionMass (xyz),
//        velocityVolume (w: V0), kirchhoffStress, blockMap, colliders,
//        gridMomentumMass (the nodes' masses and when measuring the sums and when pushing the atomics' old values),
//        gridImpulse (pushing in PIC/FLIP: the atomics' old values),
//        watchdog (the reports' and the ledger's atomics' old values).
// Writes: gridMomentumMass (pushing in an explicit APIC step: the impulses go to the momentum sums),
//         gridImpulse (pushing in PIC/FLIP: the impulse sums),
//         colliders (pushing: the bodies' entries' sums),
//         watchdog (overflows and the bodies' loads when pushing and the ledger's flows when measuring).
// The images need no affine velocity: without APIC's buffer the pass keeps within llvmpipe's 16 storage blocks with
// PIC/FLIP's impulse sums (docs/platform.md).
#define FIRN_WITHOUT_AFFINE
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/mirror.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

uniform uint measuringWork;  // 0: push the nodes and the body; 1: measure half of the pushes' work

// The image of particle p across body i's surface, whose signed distance at x is φ (0 < φ < the kernel's reach)
// with outward normal n.
void scatterImage(uint i, uint p, vec3 x, float distanceM, vec3 normal) {
  ColliderParams body = colliders[i];
  vec3 image = x - 2.0 * distanceM * normal;
  mat3 reflection = mat3(1.0) - 2.0 * outerProduct(normal, normal);
  // Times −Δt V0 / (momentum unit): the impulse per ∇w, as P2G's (common/scatter.glsl).
  mat3 impulseUnits =
      (velocityVolume[p].w * impulseUnitsPerPaM3) * (reflection * kirchhoffStress[p] * reflection);
  Stencil stencil = particleStencil(image);
  float particleU = particleDither(image);
  // The body's share, summed over the stencil here and added once: one pair of 64-bit sums per image, not per node.
  vec3 pivotM = colliderPivot(body, timeS);
  GridVector nodesTook = GridVector(0);  // in the nodes' units: the body takes exactly their opposite
  vec3 bodyMomentKgM2PerS = vec3(0.0);
  // The images' push is no force of the snow's own energy: what it does to the nodes, as they move relative to the
  // body's surface, is energy the coupling makes. A node of mass m at v⁻ that takes the pushes' sum J moves at
  // v⁺ = v⁻ + J/m and gains J · ½ (v⁻ + v⁺) exactly: half of Σ J_image · (v − v_s) is measured at v⁻, before the
  // pushes, and half at v⁺, after.
  float madeJ = 0.0;
  // The stencil's nodes in the body's rest frame: its first node's, and a cell along each axis turned into it, so
  // that a node's side of the surface costs the shape's distance alone, not two turns by quaternions per node.
  vec3 baseM = nodePosition(stencil.baseNode);
  vec3 restBase = colliderRestPoint(body, baseM, timeS);
  mat3 restCells = mat3(colliderRestPoint(body, baseM + vec3(cellSizeM, 0.0, 0.0), timeS) - restBase,
                        colliderRestPoint(body, baseM + vec3(0.0, cellSizeM, 0.0), timeS) - restBase,
                        colliderRestPoint(body, baseM + vec3(0.0, 0.0, cellSizeM), timeS) - restBase);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    ivec3 k = stencilOffset(n);
    ivec3 node = stencil.baseNode + k;
    if (any(lessThan(node, ivec3(0))) || any(greaterThanEqual(node, gridNodes))) continue;
    vec3 nodeM = nodePosition(node);
    vec3 restNormal;
    if (colliderRestDistance(body, restBase + restCells * vec3(k), restNormal) <= 0.0) continue;  // the body's own
    int address = nodeAddress(node);
    if (address < 0 || gridMomentumMass[address].w == 0) continue;  // no snow there: nothing to push
    vec3 impulse = impulseUnits * stencilGradient(stencil, k);
    ivec4 overflow = ivec4(0);
    GridVector stored = quantize(vec4(impulse, 0.0), IMPULSE_CHANNELS, contributionDither(particleU, n), overflow);
    vec3 pushKgMPerS = storedToNondimensional(stored).xyz * momentumUnitKgMPerS;
    if (measuringWork != 0u) {
      vec4 sums = storedToNondimensional(gridMomentumMass[address]);
      vec3 nodeVelocity = sums.xyz * (momentumUnitKgMPerS / (sums.w * referenceMassKg));
      madeJ += 0.5 * dot(pushKgMPerS, nodeVelocity - colliderVelocity(body, nodeM, timeS));
      continue;
    }
    reportAccumulatorOverflow(overflow, node, IMPULSE_CHANNELS);
#ifdef FIRN_GRID_IMPULSE
    addImpulseToNode(uint(address), stored.xyz, node);
#else
    addToNode(uint(address), GridVector(stored.xyz, 0), node);
#endif
    nodesTook += stored;
    bodyMomentKgM2PerS += cross(nodeM - pivotM, -pushKgMPerS);
  }
  if (measuringWork != 0u) {
    addEnergyFlows(vec4(0.0, 0.0, madeJ, 0.0));
    return;
  }
  vec3 tookKgMPerS = storedToNondimensional(nodesTook).xyz * momentumUnitKgMPerS;
  addToRigidBody(i, -tookKgMPerS, bodyMomentKgM2PerS);
  // The body's load (bodies.csv): the push it gave the snow here, at its surface's velocity where the particle is.
  addObjectLoad(i, tookKgMPerS, dot(tookKgMPerS, colliderVelocity(body, x, timeS)));
}

void main() {
  uint entry = invocationIndex();
  if (entry >= mirrorDispatch.w) return;
  uint p = particleRanks[entry];
  vec3 x = positionMass[p].xyz;
  float reachM = mirrorReachM();
  for (uint i = 0u; i < colliderCount; ++i) {
    vec3 normal;
    float distanceM = mirroredDistance(i, x, reachM, normal);
    if (distanceM > 0.0 && distanceM < reachM) scatterImage(i, p, x, distanceM, normal);
  }
}
