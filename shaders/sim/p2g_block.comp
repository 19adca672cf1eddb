#version 430 core
// Particle to grid, shaped for GPUs: work groups over the active blocks (common/blocks.glsl, workGroupCount), an
// invocation per particle of a block (in the sorted order). Each invocation adds its particle's contributions
// (common/scatter.glsl), each quantized on its own (common/grid.glsl), to the block's region in shared memory with
// integer atomics; then the group adds each region node's sums to the grid with one global atomic per channel. A
// block's particles have their base nodes in it, so their stencils reach the BLOCK_REGION_WIDTH³ nodes from its first
// node on.
//
// The sums are the tile pass's (p2g.comp): the same quantized contributions, added in another order, and integer
// sums do not depend on the order. Which of the two runs is chosen by timing both (sim/TransferShape.h), never by
// the scene. Fixed point only: float sums depend on the order, so a float scene keeps the tile pass.
// Reads: blockTable (blockCounts and slots[]), sortedParticles, positionMass, velocityVolume, kirchhoffStress,
//        affine (APIC), blockMap, gridMomentumMass (the atomics' old values), gridImpulse (the atomics' old values),
//        watchdog (the reports' atomics' old values).
// Writes: gridMomentumMass (the momentum and mass sums with an explicit APIC step's impulse),
//         gridImpulse (PIC/FLIP or semi-implicit: the impulse sums), watchdog (overflows and non-finite particles).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/scatter.glsl"

layout(local_size_x = FIRN_P2G_BLOCK_GROUP_SIZE) in;

#ifdef FIRN_GRID_IMPULSE
const int REGION_CHANNELS = 7;  // momentum x, y, z, mass; impulse x, y, z
#else
const int REGION_CHANNELS = 4;
#endif

// The region's sums, channel after channel (a scalar per channel: integer atomics take scalars), and the channels
// whose partial sums overflowed (their sign bits, as p2g.comp's accumulators mark them).
shared int regionSums[REGION_CHANNELS * BLOCK_REGION_NODES];
shared int regionOverflow[REGION_CHANNELS];

// Adds `value` to channel `channel` of region node i; returns the partial sum's overflow in its sign bit.
int addToRegion(int channel, int i, int value) {
  int previous = atomicAdd(regionSums[channel * BLOCK_REGION_NODES + i], value);
  int total = previous + value;
  return (previous ^ total) & (value ^ total);
}

// Marks the channel for the block's report when `overflow` has its sign bit set.
void markRegionOverflow(int channel, int overflow) {
  if (overflow < 0) atomicOr(regionOverflow[channel], overflow);
}

// The particle's contributions to its stencil's nodes, each channel written out (a vector's component at a variable
// index costs NVIDIA's compiler a chain of branches). The overflows are gathered, sign bit per channel, and marked
// once after the last node, so that no atomic's result holds up the next.
void scatterParticle(uint p, ivec3 blockFirstNode) {
  Contribution contribution = particleContribution(p);
  if (!contribution.finite) {
    reportNonFinite(p);
    return;
  }
  Stencil stencil = particleStencil(contribution.x);
  ivec3 baseInRegion = stencil.baseNode - blockFirstNode;
  ivec4 momentumMassOverflow = ivec4(0);  // too large to quantize, or a partial sum overflowed
#ifdef FIRN_GRID_IMPULSE
  ivec4 impulseOverflow = ivec4(0);
#endif
  StencilWalk walk = beginStencilWalk(stencil);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    vec4 nodeMomentumMass;
    vec3 nodeImpulse;
    contributionToNode(contribution, stencil.baseNode + walk.k, walkWeight(walk), walkGradient(walk),
                       nodeMomentumMass, nodeImpulse);
    float dither = contributionDither(contribution.particleU, n);
    int i = blockRegionIndex(baseInRegion + walk.k);
    ivec4 momentumMass = quantize(nodeMomentumMass, MOMENTUM_MASS_CHANNELS, dither, momentumMassOverflow);
    momentumMassOverflow |= ivec4(addToRegion(0, i, momentumMass.x), addToRegion(1, i, momentumMass.y),
                                  addToRegion(2, i, momentumMass.z), addToRegion(3, i, momentumMass.w));
#ifdef FIRN_GRID_IMPULSE
    ivec4 impulse = quantize(vec4(nodeImpulse, 0.0), IMPULSE_CHANNELS, dither, impulseOverflow);
    impulseOverflow |=
        ivec4(addToRegion(4, i, impulse.x), addToRegion(5, i, impulse.y), addToRegion(6, i, impulse.z), 0);
#endif
    advanceStencilWalk(walk);
  }
  markRegionOverflow(0, momentumMassOverflow.x);
  markRegionOverflow(1, momentumMassOverflow.y);
  markRegionOverflow(2, momentumMassOverflow.z);
  markRegionOverflow(3, momentumMassOverflow.w);
#ifdef FIRN_GRID_IMPULSE
  markRegionOverflow(4, impulseOverflow.x);
  markRegionOverflow(5, impulseOverflow.y);
  markRegionOverflow(6, impulseOverflow.z);
#endif
}

void transferBlock(uint slot) {
  uint local = gl_LocalInvocationIndex;
  for (uint i = local; i < uint(REGION_CHANNELS * BLOCK_REGION_NODES); i += uint(FIRN_P2G_BLOCK_GROUP_SIZE)) {
    regionSums[i] = 0;
  }
  if (local < uint(REGION_CHANNELS)) regionOverflow[local] = 0;
  barrier();

  ivec3 blockFirstNode = blockCoordinates(slots[slot].block) * BLOCK_WIDTH;
  uint first = slots[slot].firstParticle;
  uint count = slots[slot].particles;
  for (uint j = local; j < count; j += uint(FIRN_P2G_BLOCK_GROUP_SIZE)) {
    scatterParticle(sortedParticles[first + j], blockFirstNode);
  }
  barrier();

  // An overflow is named at the block's first node: its particles' stencils reach a few nodes further.
  if (local == 0u) {
    ivec4 momentumMassOverflow = ivec4(regionOverflow[0], regionOverflow[1], regionOverflow[2], regionOverflow[3]);
    reportAccumulatorOverflow(momentumMassOverflow, blockFirstNode, MOMENTUM_MASS_CHANNELS);
#ifdef FIRN_GRID_IMPULSE
    ivec4 impulseOverflow = ivec4(regionOverflow[4], regionOverflow[5], regionOverflow[6], 0);
    reportAccumulatorOverflow(impulseOverflow, blockFirstNode, IMPULSE_CHANNELS);
#endif
  }
  StencilBlocks blocks = stencilBlocks(blockFirstNode);
  for (uint i = local; i < uint(BLOCK_REGION_NODES); i += uint(FIRN_P2G_BLOCK_GROUP_SIZE)) {
    int node = int(i);
    ivec4 momentumMass = ivec4(regionSums[node], regionSums[BLOCK_REGION_NODES + node],
                               regionSums[2 * BLOCK_REGION_NODES + node], regionSums[3 * BLOCK_REGION_NODES + node]);
#ifdef FIRN_GRID_IMPULSE
    ivec3 impulse = ivec3(regionSums[4 * BLOCK_REGION_NODES + node], regionSums[5 * BLOCK_REGION_NODES + node],
                          regionSums[6 * BLOCK_REGION_NODES + node]);
    if (momentumMass == ivec4(0) && impulse == ivec3(0)) continue;
#else
    if (momentumMass == ivec4(0)) continue;
#endif
    ivec3 offset = blockRegionOffset(node);
    int address = stencilNodeAddress(blocks, offset);
    if (address < 0) continue;  // a block past the pool's capacity: the host sees the count and grows the pool
    addToNode(uint(address), momentumMass, blockFirstNode + offset);
#ifdef FIRN_GRID_IMPULSE
    addImpulseToNode(uint(address), impulse, blockFirstNode + offset);
#endif
  }
}

void main() {
  // The slots are the group's alike: every invocation meets every barrier.
  for (uint slot = workGroupSlot(); slot < activeBlocks(); slot += workGroupCount()) {
    transferBlock(slot);
    barrier();  // the region's sums added to the grid before the next block's clear them
  }
}
