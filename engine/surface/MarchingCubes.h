#pragma once
// The marching-cubes table (Lorensen & Cline 1987), generated here from one rule rather than copied, so that its
// source and its correctness are both on this page: for each of the 256 cases of a cell's corners inside the
// surface (field ≥ iso) or not, the triangles that separate them, as edges of the cell (the numbering of
// shaders/surface/surface_contract.h).
//
// The rule: on each face of the cell, the edges the surface crosses are joined in pairs by segments; on a face
// whose inside corners are diagonal (the ambiguous face), each inside corner is cut off by its own segment, so
// inside corners that meet only diagonally are never joined. Both cells sharing a face see the same four corners
// and so draw the same segments there: the surface has no cracks between cells (the known defect of the original
// 15-case table; Nielson & Hamann 1991). The segments of a case join into closed loops, each edge vertex in exactly
// one; each loop is a fan of triangles from an apex none of whose diagonals lies on a face (where the
// neighbouring cell could draw the same diagonal). So the mesh of a field whose outer nodes are outside is closed,
// and each edge of it is shared by exactly two triangles (tests/unit/MarchingCubesTest.cpp meshes random fields). Segments run with the inside on their right as seen from outside
// the cell, which orients every triangle counter-clockwise seen from outside the surface: its normal points down
// the field, out of the snow.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

namespace firn::surface {

struct MarchingCubesCase {
  int triangleCount = 0;
  std::array<std::uint8_t, 15> edges{};  // 3 per triangle (MAX_CELL_TRIANGLES of them), edge numbers 0–11
};

// The 256 cases, indexed by the mask of inside corners (bit c for corner c).
const std::array<MarchingCubesCase, 256>& marchingCubesCases();

// The cases as the GPU reads them (shaders/surface/emit_mesh.comp): x the triangle count, and the edges as 4-bit
// nibbles, 8 per uint, in y and z.
std::vector<glm::uvec4> packedMarchingCubesCases();

}  // namespace firn::surface
