#include "voxelizer/MassProperties.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>

namespace firn::voxelizer {
namespace {

// Below this fraction of the tetrahedra's total unsigned volume Σ|V_i| the signed sum is cancellation, not a solid:
// each of the n terms rounds by about ε |V_i|, so the sum's rounding stays near n ε Σ|V_i| ≪ 1e-9 Σ|V_i| for any
// mesh up to ~10⁶ triangles.
constexpr double kLeastVolumeFraction = 1e-9;

// Eberly 2002, "Polyhedral Mass Properties (Revisited)", Subexpressions: for one coordinate w of a triangle's
// corners, the sums f1 = Σ w_i, f2 = Σ_{i≤j} w_i w_j, f3 = Σ_{i≤j≤k} w_i w_j w_k and g_i = f2 + w_i (f1 + w_i).
struct Subexpressions {
  double f1, f2, f3, g0, g1, g2;
};

Subexpressions subexpressions(double w0, double w1, double w2) {
  const double temp0 = w0 + w1;
  const double temp1 = w0 * w0;
  const double temp2 = temp1 + w1 * temp0;
  Subexpressions s{};
  s.f1 = temp0 + w2;
  s.f2 = temp2 + w2 * s.f1;
  s.f3 = w0 * temp1 + w1 * temp2 + w2 * s.f2;
  s.g0 = s.f2 + w0 * (s.f1 + w0);
  s.g1 = s.f2 + w1 * (s.f1 + w1);
  s.g2 = s.f2 + w2 * (s.f1 + w2);
  return s;
}

std::string shortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

}  // namespace

MassProperties massProperties(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) throw MeshError("the mesh has no triangles, so it encloses no volume");
  const MeshSurface surface = measureSurface(mesh);
  if (surface.open()) {
    throw MeshError("the mesh is open (" + std::to_string(surface.boundaryEdges) +
                    " edges border holes), so it encloses no definite volume, centre of mass or inertia; close it");
  }
  // The integrals below count each triangle by the way it faces: one wound against its neighbours subtracts what
  // it should add, and the mass would be silently wrong.
  if (surface.misorientedEdges > 0) {
    throw MeshError("the mesh's faces are not consistently oriented (" + std::to_string(surface.misorientedEdges) +
                    " edges join triangles wound opposite ways), so its volume integrals are not its solid's mass, "
                    "centre of mass or inertia; orient its faces consistently (in Blender: Mesh > Normals > Recalculate "
                    "Outside)");
  }
  // The integrals are taken about the centre of the mesh's box, not the file's origin: a mesh placed far from the
  // origin would otherwise lose its digits to cancellation in x², xy and the parallel-axis shift back.
  const Bounds box = bounds(mesh);
  const glm::dvec3 referenceM = 0.5 * (box.minM + box.maxM);

  // Eberly 2002, ComputeMassProperties: ∫1, ∫x, ∫y, ∫z, ∫x², ∫y², ∫z², ∫xy, ∫yz, ∫zx over the enclosed volume, each
  // as a sum over the faces of the divergence theorem's surface integrals, scaled at the end.
  double integral[10] = {};
  double unsignedSixVolume = 0;
  for (const glm::uvec3& triangle : mesh.triangles) {
    const glm::dvec3 p0 = mesh.vertices[triangle.x] - referenceM;
    const glm::dvec3 p1 = mesh.vertices[triangle.y] - referenceM;
    const glm::dvec3 p2 = mesh.vertices[triangle.z] - referenceM;
    const glm::dvec3 d = glm::cross(p1 - p0, p2 - p0);  // the face's normal times twice its area
    const Subexpressions x = subexpressions(p0.x, p1.x, p2.x);
    const Subexpressions y = subexpressions(p0.y, p1.y, p2.y);
    const Subexpressions z = subexpressions(p0.z, p1.z, p2.z);
    integral[0] += d.x * x.f1;
    integral[1] += d.x * x.f2;
    integral[2] += d.y * y.f2;
    integral[3] += d.z * z.f2;
    integral[4] += d.x * x.f3;
    integral[5] += d.y * y.f3;
    integral[6] += d.z * z.f3;
    integral[7] += d.x * (p0.y * x.g0 + p1.y * x.g1 + p2.y * x.g2);
    integral[8] += d.y * (p0.z * y.g0 + p1.z * y.g1 + p2.z * y.g2);
    integral[9] += d.z * (p0.x * z.g0 + p1.x * z.g1 + p2.x * z.g2);
    unsignedSixVolume += std::abs(glm::dot(p0, glm::cross(p1, p2)));
  }
  const double scale[10] = {1.0 / 6, 1.0 / 24, 1.0 / 24, 1.0 / 24, 1.0 / 60, 1.0 / 60, 1.0 / 60, 1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (int i = 0; i < 10; ++i) integral[i] *= scale[i];

  const double unsignedVolumeM3 = unsignedSixVolume / 6;
  if (!(std::abs(integral[0]) > kLeastVolumeFraction * unsignedVolumeM3)) {
    throw MeshError("the mesh encloses no volume (its signed volume, " + shortNumber(integral[0]) +
                    " m³, is rounding beside its tetrahedra's " + shortNumber(unsignedVolumeM3) +
                    " m³): it is flat, or as much of it faces inward as outward");
  }
  // Every face turned over negates every integral: an inward mesh is measured as its outward twin.
  if (integral[0] < 0) {
    for (double& value : integral) value = -value;
  }

  MassProperties result;
  result.volumeM3 = integral[0];
  const glm::dvec3 centroidFromReferenceM = glm::dvec3(integral[1], integral[2], integral[3]) / result.volumeM3;
  result.centroidM = referenceM + centroidFromReferenceM;
  // ∫(|r|² I − r rᵀ) dV about the reference point, then moved to the centroid (parallel-axis theorem).
  const glm::dvec3& c = centroidFromReferenceM;
  const double v = result.volumeM3;
  const double xx = integral[5] + integral[6] - v * (c.y * c.y + c.z * c.z);
  const double yy = integral[4] + integral[6] - v * (c.z * c.z + c.x * c.x);
  const double zz = integral[4] + integral[5] - v * (c.x * c.x + c.y * c.y);
  const double xy = -(integral[7] - v * c.x * c.y);
  const double yz = -(integral[8] - v * c.y * c.z);
  const double zx = -(integral[9] - v * c.z * c.x);
  result.inertiaPerDensityM5 = glm::dmat3(xx, xy, zx,  //
                                          xy, yy, yz,  //
                                          zx, yz, zz);
  return result;
}

}  // namespace firn::voxelizer
