#version 430 core
// Particle to grid, shaped for GPUs: a work group per active block, an invocation per particle of it (in the sorted
// order, common/blocks.glsl). Each invocation adds its particle's contributions (common/scatter.glsl), each
// quantized on its own (common/grid.glsl), to the block's region in shared memory with integer atomics; then the
// group adds each region node's sums to the grid with one global atomic per channel. A block's particles have their
// base nodes in it, so their stencils reach the BLOCK_REGION_WIDTH³ nodes from its first node on.
//
// The sums are the tile pass's (p2g.comp): the same quantized contributions, added in another order, and integer
// sums do not depend on the order. Which of the two runs is chosen by timing both (sim/TransferShape.h), never by
// the scene. Fixed point only: float sums depend on the order, so a float scene keeps the tile pass.
// Reads: particle state, the block table and map, sortedParticles. Writes: grid sums, the watchdog.
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

// Adds the quantized `values` to channels [firstChannel, firstChannel + channels) of region node i, and marks the
// channels whose contribution was too large to quantize (`tooLarge`, from quantize) or whose partial sum overflowed.
void addToRegion(int i, int firstChannel, int channels, ivec4 values, ivec4 tooLarge) {
  for (int c = 0; c < channels; ++c) {
    int over = tooLarge[c];
    if (values[c] != 0) {
      int previous = atomicAdd(regionSums[(firstChannel + c) * BLOCK_REGION_NODES + i], values[c]);
      int total = previous + values[c];
      over |= (previous ^ total) & (values[c] ^ total);
    }
    if (over < 0) atomicOr(regionOverflow[firstChannel + c], over);
  }
}

void scatterParticle(uint p, ivec3 blockFirstNode) {
  Contribution contribution = particleContribution(p);
  if (!contribution.finite) {
    reportNonFinite(p);
    return;
  }
  Stencil stencil = particleStencil(contribution.x);
  ivec3 baseInRegion = stencil.baseNode - blockFirstNode;
  for (int n = 0; n < KERNEL_NODES; ++n) {
    ivec3 k = stencilOffset(n);
    vec4 nodeMomentumMass;
    vec3 nodeImpulse;
    contributionToNode(contribution, stencil.baseNode + k, stencilWeight(stencil, k), stencilGradient(stencil, k),
                       nodeMomentumMass, nodeImpulse);
    float dither = contributionDither(contribution.particleU, n);
    int i = blockRegionIndex(baseInRegion + k);
    ivec4 tooLarge = ivec4(0);
    ivec4 momentumMass = quantize(nodeMomentumMass, MOMENTUM_MASS_CHANNELS, dither, tooLarge);
    addToRegion(i, 0, 4, momentumMass, tooLarge);
#ifdef FIRN_GRID_IMPULSE
    tooLarge = ivec4(0);
    ivec4 impulse = quantize(vec4(nodeImpulse, 0.0), IMPULSE_CHANNELS, dither, tooLarge);
    addToRegion(i, 4, 3, impulse, tooLarge);
#endif
  }
}

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;  // the whole group: no barrier is left waiting
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
