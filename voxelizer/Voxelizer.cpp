#include "voxelizer/Voxelizer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

namespace firn::voxelizer {
namespace {

std::string describeBox(const Bounds& box) {
  char text[160];
  std::snprintf(text, sizeof text, "[%.4g, %.4g, %.4g] to [%.4g, %.4g, %.4g] m", box.minM.x, box.minM.y, box.minM.z,
                box.maxM.x, box.maxM.y, box.maxM.z);
  return text;
}

std::string metres(double valueM) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g m", valueM);
  return text;
}

}  // namespace

std::vector<glm::dvec3> voxelize(const TriangleMesh& mesh, const SamplingOptions& options) {
  const WindingNumber windingNumber(mesh);
  const Bounds box = bounds(mesh);
  // The box test first: it is free, and it keeps the lattice's jittered candidates beyond the box out even
  // where an open mesh's winding number reaches 0.5 there.
  return samplePoints(
      box,
      [&](const glm::dvec3& pointM) {
        return glm::all(glm::greaterThanEqual(pointM, box.minM)) && glm::all(glm::lessThanEqual(pointM, box.maxM)) &&
               windingNumber.inside(pointM);
      },
      options);
}

SampleEstimate estimateVoxelize(const TriangleMesh& mesh, const SamplingOptions& options) {
  const Bounds box = bounds(mesh);
  // Each axis counts at least one spacing, so that a box flat along an axis still gets a lattice across it.
  const glm::dvec3 extentM = glm::max(box.maxM - box.minM, glm::dvec3(options.spacingM));
  SamplingOptions coarse = options;
  coarse.sampler = Sampler::Lattice;
  coarse.spacingM = std::max(options.spacingM, std::cbrt(extentM.x * extentM.y * extentM.z / kEstimateLatticePoints));
  coarse.maxPoints = static_cast<std::size_t>(4 * kEstimateLatticePoints);  // the coarse lattice's own points bound it
  coarse.progress = nullptr;
  const double coarseCellM3 = coarse.spacingM * coarse.spacingM * coarse.spacingM;
  const double volumeM3 = double(voxelize(mesh, coarse).size()) * coarseCellM3;
  return estimateSamples(box, volumeM3, measureSurface(mesh).areaM2, options);
}

std::string whyNoParticles(const TriangleMesh& mesh, const MeshSurface& surface, double spacingM) {
  const Bounds box = bounds(mesh);
  const glm::dvec3 extentM = box.maxM - box.minM;
  const double thinnestM = std::min({extentM.x, extentM.y, extentM.z});
  // A lattice a quarter of the thinnest extent apart puts points across every part at least that thick.
  constexpr double spacingsAcross = 4;
  std::string message = "no particles: the mesh's bounds are " + describeBox(box) + ", " + metres(thinnestM) +
                        " at their thinnest, ";
  if (thinnestM < spacingsAcross * spacingM) {
    return message + "too thin for the particle spacing " + metres(spacingM) + "; a spacing of " +
           metres(thinnestM / spacingsAcross) + " or less would fill it (or scale the mesh up)";
  }
  if (surface.open()) {
    return message + "and no point of the lattice at spacing " + metres(spacingM) +
           " lies inside it: it is open (" + std::to_string(surface.boundaryEdges) +
           " edges border holes) and encloses nothing where its generalized winding number reaches ½; close it";
  }
  // A closed shape's typical thickness: a plate of thickness t has volume A t / 2.
  const double thicknessM = 2 * std::abs(signedVolume(mesh)) / surface.areaM2;
  return message + "yet no point of the lattice at spacing " + metres(spacingM) +
         " lies inside it: its parts are about " + metres(thicknessM) + " thick; a spacing of " +
         metres(thicknessM / spacingsAcross) + " or less would fill them";
}

std::string sheetWarning(const MeshSurface& surface, std::size_t particles, double spacingM) {
  if (!surface.open() || !(surface.areaM2 > 0)) return "";
  const double layerM = double(particles) * spacingM * spacingM * spacingM / surface.areaM2;
  // Less than one spacing on average is at most one layer of particles: a sheet, however it is spread.
  if (layerM >= spacingM) return "";
  char area[32];
  std::snprintf(area, sizeof area, "%.3g m²", surface.areaM2);
  return "the mesh is open (" + std::to_string(surface.boundaryEdges) + " edges border holes) and its " +
         std::to_string(particles) + " particles cover its " + area + " of surface only " + metres(layerM) +
         " thick on average, less than the spacing " + metres(spacingM) +
         ": it encloses next to no volume, and fills as a sheet along its surface; close the mesh";
}

}  // namespace firn::voxelizer
