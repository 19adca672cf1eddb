// What classify_cells.comp finds per node and emit_mesh.comp reads: the marching-cubes case of the cell whose
// first node it is, and which of the node's own three edges (towards +x, +y, +z) the surface crosses.
// Needs surface_common.glsl.

layout(std430, binding = FIRN_BINDING_SURFACE_CELLS) buffer SurfaceCellBuffer { uint cells[]; };
// The marching-cubes table (engine/surface/MarchingCubes.h), a case per cell's corner pattern.
layout(std140, binding = FIRN_BINDING_SURFACE_CASES) uniform SurfaceCaseBlock { uvec4 cases[MARCHING_CUBES_CASES]; };

uint cellCase(uint cell) { return cell & 0xFFu; }
uint crossedEdges(uint cell) { return (cell >> 8) & 7u; }
uint packCell(uint caseIndex, uint crossed) { return caseIndex | (crossed << 8); }
