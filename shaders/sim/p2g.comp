#version 430 core
// Particle to grid: an invocation per row of ROW_NODES base nodes along x that holds particles, fullest rows
// first (common/blocks.glsl). The invocation sums its row's particles' contributions (common/scatter.glsl), each
// quantized on its own (common/grid.glsl), into private accumulators over the REGION_NODES nodes the row's
// stencils reach, then adds each accumulator to its node with one atomic per channel. The row's particles share
// their nodes, so this takes a few atomics per particle where one per particle, node and channel took 27 to 448;
// and the accumulators' indices are the same in every invocation, which a CPU renderer runs as vector code.
// Reads: particle state, the block table and map, bins, sortedParticles. Writes: grid sums, the watchdog.
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/scatter.glsl"

layout(local_size_x = FIRN_ROW_GROUP_SIZE) in;

const int REGION_WIDTH = ROW_NODES + KERNEL_WIDTH - 1;  // nodes along x
const int REGION_NODES = REGION_WIDTH * KERNEL_WIDTH * KERNEL_WIDTH;

// The accumulators, and their overflows (common/grid.glsl: fixed point marks them, float leaves them 0).
GridVector momentumMass[REGION_NODES];
ivec4 momentumMassOverflow[REGION_NODES];
#ifndef FIRN_TRANSFER_APIC
GridVector impulses[REGION_NODES];  // w unused
ivec4 impulseOverflow[REGION_NODES];
#endif

int regionIndex(ivec3 offset) { return offset.x + REGION_WIDTH * (offset.y + KERNEL_WIDTH * offset.z); }
ivec3 regionOffset(int index) {
  return ivec3(index % REGION_WIDTH, (index / REGION_WIDTH) % KERNEL_WIDTH, index / (REGION_WIDTH * KERNEL_WIDTH));
}

// Adds the contribution to the stencil's node k (an offset from its base node) to its accumulator; the particle's
// base node is the row's bx-th. Called with k.x a constant, so that the weights along x are read at fixed places.
void scatterToNode(Contribution contribution, Stencil stencil, ivec3 k, int bx) {
  ivec3 node = stencil.baseNode + k;
  vec4 nodeMomentumMass;
  vec3 nodeImpulse;
  contributionToNode(contribution, node, stencilWeight(stencil, k), stencilGradient(stencil, k), nodeMomentumMass,
                     nodeImpulse);
  float dither = contributionDither(contribution.particleU, k.x + KERNEL_WIDTH * (k.y + KERNEL_WIDTH * k.z));
  int i = regionIndex(ivec3(bx, 0, 0) + k);
  accumulate(momentumMass[i], quantize(nodeMomentumMass, MOMENTUM_MASS_CHANNELS, dither, momentumMassOverflow[i]),
             momentumMassOverflow[i]);
#ifndef FIRN_TRANSFER_APIC
  accumulate(impulses[i], quantize(vec4(nodeImpulse, 0.0), IMPULSE_CHANNELS, dither, impulseOverflow[i]),
             impulseOverflow[i]);
#endif
}

// Adds particle p, whose base node is the row's bx-th, to the accumulators: the stencil row by row along x, each
// row written out (KERNEL_WIDTH² loop iterations per particle).
void scatterParticle(uint p, int bx) {
  Contribution contribution = particleContribution(p);
  if (!contribution.finite) {
    reportNonFinite(p);
    return;
  }
  Stencil stencil = particleStencil(contribution.x);
  for (int yz = 0; yz < KERNEL_WIDTH * KERNEL_WIDTH; ++yz) {
    ivec3 k = ivec3(0, yz % KERNEL_WIDTH, yz / KERNEL_WIDTH);
    scatterToNode(contribution, stencil, k, bx);
    scatterToNode(contribution, stencil, k + ivec3(1, 0, 0), bx);
    scatterToNode(contribution, stencil, k + ivec3(2, 0, 0), bx);
#ifdef FIRN_KERNEL_CUBIC
    scatterToNode(contribution, stencil, k + ivec3(3, 0, 0), bx);
#endif
  }
}

void main() {
  uint entry = workGroupSlot() * uint(FIRN_ROW_GROUP_SIZE) + gl_LocalInvocationIndex;
  if (entry >= rowCounts.x) return;
  uint slot = rowOrder[entry] / uint(BLOCK_ROWS);
  uint row = rowOrder[entry] % uint(BLOCK_ROWS);
  uvec2 rowBins[ROW_NODES];  // each bin's first particle in the sorted order, its particles
  uint rowParticles = 0u;
  for (int bx = 0; bx < ROW_NODES; ++bx) {
    rowBins[bx] = binParticles(slot, row * uint(ROW_NODES) + uint(bx));
    rowParticles += rowBins[bx].y;
  }
  if (rowParticles == 0u) return;

  for (int i = 0; i < REGION_NODES; ++i) {
    momentumMass[i] = GridVector(0);
    momentumMassOverflow[i] = ivec4(0);
#ifndef FIRN_TRANSFER_APIC
    impulses[i] = GridVector(0);
    impulseOverflow[i] = ivec4(0);
#endif
  }
  for (int bx = 0; bx < ROW_NODES; ++bx) {
    for (uint j = rowBins[bx].x; j < rowBins[bx].x + rowBins[bx].y; ++j) scatterParticle(sortedParticles[j], bx);
  }

  Row r = blockRow(slot, row);
  for (int i = 0; i < REGION_NODES; ++i) {
    ivec3 node = r.firstBase + regionOffset(i);
    reportAccumulatorOverflow(momentumMassOverflow[i], node, MOMENTUM_MASS_CHANNELS);
#ifdef FIRN_TRANSFER_APIC
    if (momentumMass[i] == GridVector(0)) continue;
#else
    reportAccumulatorOverflow(impulseOverflow[i], node, IMPULSE_CHANNELS);
    if (momentumMass[i] == GridVector(0) && impulses[i] == GridVector(0)) continue;
#endif
    int address = rowNodeAddress(r, node);
    if (address < 0) continue;  // a block past the pool's capacity: the host sees the count and grows the pool
    addToNode(uint(address), momentumMass[i], node);
#ifndef FIRN_TRANSFER_APIC
    addImpulseToNode(uint(address), impulses[i].xyz, node);
#endif
  }
}
