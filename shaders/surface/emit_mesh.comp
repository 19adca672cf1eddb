#version 430 core
// Marching cubes, last pass: per node, the vertices of its crossed edges and the triangles of its cell, written
// where the prefix scan of classify_cells.comp's counts puts them, so the mesh comes out in the order of the
// nodes whatever order the invocations run in. A vertex is made once, by the node owning its edge, and each
// triangle names it by that node's first vertex and the edge's rank among the node's crossed edges: the mesh is
// indexed, and triangles of neighbouring cells share the vertices of their common edges.
// A vertex lies where the linear interpolation of f along its edge equals the iso level; its normal is down the
// gradient of f (central differences at the edge's ends, interpolated alike); its albedo is Σ V W albedo / f,
// both sums interpolated, which is defined wherever f is (at the vertex, f = iso > 0); its velocity likewise
// Σ V W v / f, the particles' velocities weighted as the field weighs them.
// It reads the density, node sums, cells, counts (offsets) and the case table, and writes vertices and indices.
#include "surface/surface_common.glsl"
#include "surface/cells.glsl"
#include "surface/node_sums.glsl"

layout(std430, binding = FIRN_BINDING_SURFACE_DENSITY) readonly buffer SurfaceDensityBuffer { int density[]; };
layout(std430, binding = FIRN_BINDING_SURFACE_COUNTS) readonly buffer SurfaceCountBuffer { uvec2 offsets[]; };
#include "surface/vertices.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;
layout(std430, binding = FIRN_BINDING_SURFACE_INDICES) writeonly buffer SurfaceIndexBuffer { uint indices[]; };

float fieldAt(ivec3 node) { return fieldValue(density[nodeAddress(clamp(node, ivec3(0), boxNodes - 1))]); }

// ∇f by central differences (one-sided on the grid's faces), per node spacing.
vec3 fieldGradient(ivec3 node) {
  vec3 gradient;
  for (int axis = 0; axis < 3; ++axis) {
    ivec3 step = ivec3(0);
    step[axis] = 1;
    ivec3 below = max(node - step, ivec3(0)), above = min(node + step, boxNodes - 1);
    gradient[axis] = (fieldAt(above) - fieldAt(below)) / float(max(above[axis] - below[axis], 1));
  }
  return gradient;
}

SurfaceVertex edgeVertex(ivec3 start, int axis) {
  ivec3 end = start;
  end[axis] += 1;
  float startValue = fieldAt(start), endValue = fieldAt(end);
  float t = clamp((isoLevel - startValue) / (endValue - startValue), 0.0, 1.0);
  SurfaceVertex vertex;
  vec3 positionM = nodePositionM(start);
  positionM[axis] += t * nodeSpacingM;
  vertex.positionM = vec4(positionM, 1.0);
  vec3 gradient = mix(fieldGradient(start), fieldGradient(end), t);
  vec3 along = vec3(0.0);
  along[axis] = startValue > endValue ? 1.0 : -1.0;  // out of the snow along the edge, if f is flat across it
  vertex.normal = vec4(dot(gradient, gradient) > 0.0 ? -normalize(gradient) : along, 0.0);
  vertex.albedo = vec4(1.0);
  vertex.velocity = vec4(0.0);
  float densitySum = mix(float(density[nodeAddress(start)]), float(density[nodeAddress(end)]), t);
  if (withColors()) {
    vec3 colorSum = mix(vec3(nodeSums[nodeAddress(start)].color.xyz), vec3(nodeSums[nodeAddress(end)].color.xyz), t);
    vertex.albedo = vec4(clamp(colorSum / max(densitySum, 1.0), 0.0, 1.0), 1.0);
  }
  if (withVelocities()) {
    vec3 velocitySum =
        mix(vec3(nodeSums[nodeAddress(start)].velocity.xyz), vec3(nodeSums[nodeAddress(end)].velocity.xyz), t);
    vertex.velocity = vec4(velocitySum / max(densitySum, 1.0), 0.0);
  }
  return vertex;
}

// Edge e's 4-bit number in a case's packed triangles (MarchingCubes.h).
int caseEdge(uvec4 entry, int i) { return int((entry[1 + i / 8] >> (4 * (i % 8))) & 0xFu); }

void main() {
  uint address = invocationIndex();
  if (address >= nodeCount) return;
  uint cell = cells[address];
  uvec2 first = offsets[address];  // this node's first vertex and its cell's first triangle
  ivec3 node = nodeOfAddress(address);
  uint crossed = crossedEdges(cell);
  uint vertex = first.x;
  for (int axis = 0; axis < 3; ++axis) {
    if ((crossed & (1u << axis)) != 0u) vertices[vertex++] = edgeVertex(node, axis);
  }
  uvec4 entry = cases[cellCase(cell)];
  for (int i = 0; i < 3 * int(entry.x); ++i) {
    int edge = caseEdge(entry, i);
    int axis = edgeAxis(edge);
    uint owner = nodeAddress(node + edgeStart(edge));
    uint ownerCrossed = crossedEdges(cells[owner]);
    indices[3u * first.y + uint(i)] = offsets[owner].x + uint(bitCount(ownerCrossed & ((1u << axis) - 1u)));
  }
}
