#version 430 core
// Marching cubes, first pass (Lorensen & Cline 1987): per node, the case of the cell whose first corner it is
// (which corners hold f ≥ iso), the crossings of its own three edges, and so how many vertices it makes (one per
// crossed edge of its own) and how many triangles its cell does. One invocation per node; nodes on the grid's
// far faces have no cell, and edges leaving the grid belong to no node.
// It reads the density and the case table, and writes cells and counts (the prefix scan turns them into offsets).
#include "surface/surface_common.glsl"
#include "surface/cells.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

layout(std430, binding = FIRN_BINDING_SURFACE_DENSITY) readonly buffer SurfaceDensityBuffer { int density[]; };
layout(std430, binding = FIRN_BINDING_SURFACE_COUNTS) writeonly buffer SurfaceCountBuffer { uvec2 counts[]; };

bool insideAt(ivec3 node) { return density[nodeAddress(node)] >= isoUnits; }

void main() {
  uint address = invocationIndex();
  if (address >= nodeCount) return;
  ivec3 node = nodeOfAddress(address);
  bool inside = insideAt(node);
  uint crossed = 0u;
  for (int axis = 0; axis < 3; ++axis) {
    ivec3 neighbour = node;
    neighbour[axis] += 1;
    if (neighbour[axis] < boxNodes[axis] && insideAt(neighbour) != inside) crossed |= 1u << axis;
  }
  uint caseIndex = 0u;
  if (all(lessThan(node + 1, boxNodes))) {
    for (int corner = 0; corner < 8; ++corner) {
      if (insideAt(node + cellCorner(corner))) caseIndex |= 1u << corner;
    }
  }
  cells[address] = packCell(caseIndex, crossed);
  counts[address] = uvec2(uint(bitCount(crossed)), cases[caseIndex].x);
}
