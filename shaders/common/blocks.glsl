// P2G without atomics (solver.atomics "none"); its sizes and table are in common/gpu_contract.h. Particles are binned into
// blocks of BLOCK_CELLS³ cells. A particle in cell c reaches nodes c − 1 … c + 2 on each axis with either kernel
// (kernel.glsl), so a block's particles reach at most BLOCK_CELLS + 3 nodes per axis, and two blocks whose
// coordinates have the same parities (one "colour") lie 2·BLOCK_CELLS > BLOCK_CELLS + 3 nodes apart: no node is
// reached from two blocks of one colour. Scattering one colour at a time, one invocation per block, plain
// additions are race-free, on the GPU and between llvmpipe's threads alike.
//
// Passes: clear_grid.comp empties the bins of the active box, bin_count.comp counts each block's particles
// (one atomic per particle instead of seven per particle and node), bin_scan.comp turns counts into bin offsets
// and lists each colour's non-empty blocks, bin_place.comp files the particle indices, p2g_blocks.comp scatters
// one colour at a time. The sums' order within a bin follows bin_count's atomics, so like float atomics, and
// unlike fixed point, runs are not bitwise deterministic.

layout(std430, binding = FIRN_BINDING_BLOCKS) coherent buffer BlockTableBuffer {
  FIRN_MEMBERS(FIRN_BLOCK_TABLE_HEADER)
  uvec2 bins[];  // per block: first entry in blockParticles, particle count
};
layout(std430, binding = FIRN_BINDING_PARTICLE_SLOTS) buffer ParticleSlotBuffer { uint particleSlots[]; };
layout(std430, binding = FIRN_BINDING_BLOCK_PARTICLES) buffer BlockParticleBuffer { uint blockParticles[]; };
layout(std430, binding = FIRN_BINDING_BLOCK_ORDER) buffer BlockOrderBuffer { uint blockOrder[]; };

const uint NOT_BINNED = 0xffffffffu;

uint blockIndex(ivec3 block) { return uint(block.x + blocksPerAxis.x * (block.y + blocksPerAxis.y * block.z)); }

// The block of the cell holding a particle (G2P keeps particles inside the grid).
ivec3 particleBlock(vec3 positionM) {
  ivec3 cell = ivec3(floor((positionM - gridOrigin()) / cellSize()));
  return clamp(cell, ivec3(0), gridNodes.xyz - 1) / BLOCK_CELLS;
}
