#version 430 core
// Particle to grid: an invocation per tile of base nodes that holds particles, fullest tiles first
// (common/blocks.glsl). The invocation sums its tile's particles' contributions (common/scatter.glsl), each
// quantized on its own (common/grid.glsl), into private accumulators over the REGION_NODES nodes its stencils
// reach, then adds each accumulator to its node with one atomic per channel. The tile's particles share their
// nodes, so this takes a few atomics per particle where one per particle, node and channel took 27 to 448; and the
// accumulators' indices are the same in every invocation, which a CPU renderer runs as vector code.
// Reads: blockTable (tileCounts.x and slots[] and the tileDispatch record), tileOrder, bins, sortedParticles,
//        positionMass, velocityVolume, kirchhoffStress, affine (APIC), blockMap,
//        gridMomentumMass (fixed point: the atomics' old values), gridImpulse (fixed point: the atomics' old values),
//        watchdog (the reports' atomics' old values).
// Writes: gridMomentumMass (the momentum and mass sums with an explicit APIC step's impulse),
//         gridImpulse (PIC/FLIP or semi-implicit: the impulse sums), watchdog (overflows and non-finite particles).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/scatter.glsl"

layout(local_size_x = FIRN_TILE_GROUP_SIZE) in;

// The accumulators, and the overflows of any of them per channel (common/grid.glsl: fixed point marks them, float
// leaves them 0); one mark for the tile rather than one per accumulator keeps the accumulators in a CPU's cache.
GridVector momentumMass[REGION_NODES];
GridVector impulses[REGION_NODES];  // with the impulse's own storage only (grid.glsl); w unused
ivec4 momentumMassOverflow;
ivec4 impulseOverflow;

void clearAccumulators() {
  for (int i = 0; i < REGION_NODES; ++i) {
    momentumMass[i] = GridVector(0);
#ifdef FIRN_GRID_IMPULSE
    impulses[i] = GridVector(0);
#endif
  }
  momentumMassOverflow = ivec4(0);
  impulseOverflow = ivec4(0);
}

// Adds the contribution to the stencil's node k (an offset from its base node) to its accumulator; the particle's
// base node is the tile's `bin`-th. Called with k.x a constant, so that the weights along x are read at fixed places.
void scatterToNode(Contribution contribution, Stencil stencil, ivec3 k, ivec3 bin) {
  ivec3 node = stencil.baseNode + k;
  vec4 nodeMomentumMass;
  vec3 nodeImpulse;
  contributionToNode(contribution, node, stencilWeight(stencil, k), stencilGradient(stencil, k), nodeMomentumMass,
                     nodeImpulse);
  float dither = contributionDither(contribution.particleU, k.x + KERNEL_WIDTH * (k.y + KERNEL_WIDTH * k.z));
  int i = regionIndex(bin + k);
  accumulate(momentumMass[i], quantize(nodeMomentumMass, MOMENTUM_MASS_CHANNELS, dither, momentumMassOverflow),
             momentumMassOverflow);
#ifdef FIRN_GRID_IMPULSE
  accumulate(impulses[i], quantize(vec4(nodeImpulse, 0.0), IMPULSE_CHANNELS, dither, impulseOverflow), impulseOverflow);
#endif
}

// Adds particle p, whose base node is the tile's `bin`-th, to the accumulators: the stencil row by row along x,
// each row written out (KERNEL_WIDTH² loop iterations per particle).
void scatterParticle(uint p, ivec3 bin) {
  Contribution contribution = particleContribution(p);
  if (!contribution.finite) {
    reportNonFinite(p);
    return;
  }
  Stencil stencil = particleStencil(contribution.x);
  for (int yz = 0; yz < KERNEL_WIDTH * KERNEL_WIDTH; ++yz) {
    ivec3 k = ivec3(0, yz % KERNEL_WIDTH, yz / KERNEL_WIDTH);
    scatterToNode(contribution, stencil, k, bin);
    scatterToNode(contribution, stencil, k + ivec3(1, 0, 0), bin);
    scatterToNode(contribution, stencil, k + ivec3(2, 0, 0), bin);
#ifdef FIRN_KERNEL_CUBIC
    scatterToNode(contribution, stencil, k + ivec3(3, 0, 0), bin);
#endif
  }
}

void main() {
  uint entry = workGroupSlot() * uint(FIRN_TILE_GROUP_SIZE) + gl_LocalInvocationIndex;
  if (entry >= tileCounts.x) return;
  uint slot = tileOrder[entry] / uint(BLOCK_TILES);
  uint tile = tileOrder[entry] % uint(BLOCK_TILES);

  clearAccumulators();
  // Bin by bin: the bin's place in the tile is the same in every invocation.
  for (int b = 0; b < TILE_BASE_NODES; ++b) {
    uvec2 particles = binParticles(slot, tileFirstBin(tile) + uint(b));  // first, count
    ivec3 bin = ivec3(b % TILE_WIDTH, b / TILE_WIDTH, 0);
    for (uint j = particles.x; j < particles.x + particles.y; ++j) scatterParticle(sortedParticles[j], bin);
  }

  ivec3 firstBase = tileFirstBase(slot, tile);
  StencilBlocks blocks = stencilBlocks(firstBase);
  // An overflow is named at the tile's first base node: its stencils reach a few nodes further.
  reportAccumulatorOverflow(momentumMassOverflow, firstBase, MOMENTUM_MASS_CHANNELS);
  reportAccumulatorOverflow(impulseOverflow, firstBase, IMPULSE_CHANNELS);
  for (int i = 0; i < REGION_NODES; ++i) {
    ivec3 node = firstBase + regionOffset(i);
#ifdef FIRN_GRID_IMPULSE
    if (momentumMass[i] == GridVector(0) && impulses[i] == GridVector(0)) continue;
#else
    if (momentumMass[i] == GridVector(0)) continue;
#endif
    int address = stencilNodeAddress(blocks, regionOffset(i));
    if (address < 0) continue;  // a block past the pool's capacity: the host sees the count and grows the pool
    addToNode(uint(address), momentumMass[i], node);
#ifdef FIRN_GRID_IMPULSE
    addImpulseToNode(uint(address), impulses[i].xyz, node);
#endif
  }
}
