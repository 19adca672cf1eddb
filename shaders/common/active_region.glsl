// The region the particles occupy, so that grid passes cost what the particles cover and not the domain.
// Particle passes reduce their cells within the work group in shared memory, then one invocation per group
// folds the group's bounds into the buffer: a handful of global atomics per group instead of one per particle.

const int INT_MAX = 2147483647;
const int INT_MIN = -2147483647 - 1;

shared int groupCellMin[3];
shared int groupCellMax[3];

void beginBoundsReduction() {
  if (gl_LocalInvocationIndex == 0u) {
    for (int axis = 0; axis < 3; ++axis) {
      groupCellMin[axis] = INT_MAX;
      groupCellMax[axis] = INT_MIN;
    }
  }
  barrier();
}

void includeInBounds(vec3 positionM) {
  ivec3 cell = ivec3(floor((positionM - gridOrigin()) / cellSize()));
  for (int axis = 0; axis < 3; ++axis) {
    atomicMin(groupCellMin[axis], cell[axis]);
    atomicMax(groupCellMax[axis], cell[axis]);
  }
}

void endBoundsReduction() {
  barrier();
  if (gl_LocalInvocationIndex == 0u && groupCellMin[0] <= groupCellMax[0]) {
    atomicMin(region.particleCellMin.x, groupCellMin[0]);
    atomicMin(region.particleCellMin.y, groupCellMin[1]);
    atomicMin(region.particleCellMin.z, groupCellMin[2]);
    atomicMax(region.particleCellMax.x, groupCellMax[0]);
    atomicMax(region.particleCellMax.y, groupCellMax[1]);
    atomicMax(region.particleCellMax.z, groupCellMax[2]);
  }
}

// Grid passes run one invocation per node of the active box, in groups of this shape.
#define FIRN_GRID_GROUP_SIZE local_size_x = 8, local_size_y = 8, local_size_z = 4
const ivec3 GRID_GROUP_SIZE = ivec3(8, 8, 4);
