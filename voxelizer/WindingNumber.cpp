#include "voxelizer/WindingNumber.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace firn::voxelizer {
namespace {

constexpr double pi = 3.14159265358979323846;
// Leaves hold at most this many triangles: small enough that a query near the surface evaluates few exact
// solid angles, large enough that the tree stays shallow.
constexpr std::size_t maxLeafTriangles = 8;
// A balanced median split halves the triangles per level, so 2³² triangles need 29 levels below the leaves'
// size; the traversal stack holds at most one pending sibling per level.
constexpr int maxTreeDepth = 64;

}  // namespace

WindingNumber::WindingNumber(const TriangleMesh& mesh, double accuracyBeta) : accuracyBeta_(accuracyBeta) {
  // The expansion converges only outside the cluster's bounding sphere.
  if (!(accuracyBeta > 1)) throw std::invalid_argument("WindingNumber: accuracyBeta must be greater than 1");
  if (mesh.triangles.empty()) throw std::invalid_argument("WindingNumber: the mesh has no triangles");
  std::vector<Triangle> source;
  source.reserve(mesh.triangles.size());
  for (const glm::uvec3& triangle : mesh.triangles) {
    if (glm::any(glm::greaterThanEqual(triangle, glm::uvec3(static_cast<unsigned>(mesh.vertices.size()))))) {
      throw std::invalid_argument("WindingNumber: a triangle indexes past the vertices");
    }
    source.push_back({mesh.vertices[triangle.x], mesh.vertices[triangle.y], mesh.vertices[triangle.z]});
  }
  std::vector<std::uint32_t> order(source.size());
  for (std::size_t t = 0; t < order.size(); ++t) order[t] = static_cast<std::uint32_t>(t);
  triangles_.reserve(source.size());
  nodes_.reserve(source.size() / (maxLeafTriangles / 2) * 2 + 1);  // median splits leave ≥ maxLeaf/2 per leaf
  build(order, 0, order.size(), source);
}

glm::dvec3 WindingNumber::areaNormal(const Triangle& triangle) {
  return 0.5 * glm::cross(triangle.bM - triangle.aM, triangle.cM - triangle.aM);
}

glm::dvec3 WindingNumber::centroid(const Triangle& triangle) { return (triangle.aM + triangle.bM + triangle.cM) / 3.0; }

// The signed solid angle that triangle (a, b, c) subtends at p, by Van Oosterom and Strackee 1983:
// tan(Ω/2) = a·(b×c) / (|a||b||c| + (a·b)|c| + (b·c)|a| + (c·a)|b|), with a, b, c relative to p. Positive when
// p lies behind the triangle, opposite its normal (b − a) × (c − a): inside, for an outward-facing surface.
double WindingNumber::solidAngle(const Triangle& triangle, const glm::dvec3& pointM) {
  const glm::dvec3 a = triangle.aM - pointM;
  const glm::dvec3 b = triangle.bM - pointM;
  const glm::dvec3 c = triangle.cM - pointM;
  const double lengthA = glm::length(a);
  const double lengthB = glm::length(b);
  const double lengthC = glm::length(c);
  const double numerator = glm::dot(a, glm::cross(b, c));
  const double denominator = lengthA * lengthB * lengthC + glm::dot(a, b) * lengthC + glm::dot(b, c) * lengthA +
                             glm::dot(c, a) * lengthB;
  return 2 * std::atan2(numerator, denominator);
}

// Splits [begin, end) of `order` at the median triangle centroid along the centroids' longest extent, so the
// tree is balanced whatever the triangles' sizes; emits the subtree depth first and returns its root.
std::uint32_t WindingNumber::build(std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end,
                                   const std::vector<Triangle>& source) {
  const std::size_t count = end - begin;
  glm::dvec3 weightedCentroidSum(0.0);
  glm::dvec3 centroidSum(0.0);
  double areaSum = 0;
  glm::dvec3 centroidMinM(std::numeric_limits<double>::infinity());
  glm::dvec3 centroidMaxM(-std::numeric_limits<double>::infinity());
  for (std::size_t t = begin; t < end; ++t) {
    const Triangle& triangle = source[order[t]];
    const double area = glm::length(areaNormal(triangle));
    const glm::dvec3 centroidM = centroid(triangle);
    weightedCentroidSum += area * centroidM;
    centroidSum += centroidM;
    areaSum += area;
    centroidMinM = glm::min(centroidMinM, centroidM);
    centroidMaxM = glm::max(centroidMaxM, centroidM);
  }
  // A cluster of degenerate triangles has no area to weight by; their plain centroid serves (all their
  // moments are zero anyway).
  const glm::dvec3 centerM = areaSum > 0 ? weightedCentroidSum / areaSum : centroidSum / static_cast<double>(count);

  Node node{centerM, glm::dvec3(0.0), glm::dmat3(0.0), {glm::dmat3(0.0), glm::dmat3(0.0), glm::dmat3(0.0)}, 0, 0, 0, 0};
  double radiusSquaredM2 = 0;
  for (std::size_t t = begin; t < end; ++t) {
    const Triangle& triangle = source[order[t]];
    const glm::dvec3 areaNormalM2 = areaNormal(triangle);
    const glm::dvec3 centroidM = centroid(triangle);
    // Over a triangle, ∫ (x − c̃) dA = a (x_t − c̃), and ∫ (x − c̃)(x − c̃)ᵀ dA = a [(x_t − c̃)(x_t − c̃)ᵀ + C_t]
    // with C_t = Σ_v (v − x_t)(v − x_t)ᵀ / 12 the triangle's own spread about its centroid.
    const glm::dvec3 offsetM = centroidM - centerM;
    glm::dmat3 spreadM2 = glm::outerProduct(offsetM, offsetM);
    for (const glm::dvec3& vertexM : {triangle.aM, triangle.bM, triangle.cM}) {
      const glm::dvec3 fromCenterM = vertexM - centerM;
      radiusSquaredM2 = std::max(radiusSquaredM2, glm::dot(fromCenterM, fromCenterM));
      spreadM2 += glm::outerProduct(vertexM - centroidM, vertexM - centroidM) / 12.0;
    }
    node.areaNormalM2 += areaNormalM2;
    node.firstMomentM3 += glm::outerProduct(areaNormalM2, offsetM);
    for (int i = 0; i < 3; ++i) node.secondMomentM4[i] += areaNormalM2[i] * spreadM2;
  }
  node.farDistanceSquaredM2 = accuracyBeta_ * accuracyBeta_ * radiusSquaredM2;

  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back(node);
  if (count <= maxLeafTriangles) {
    nodes_[index].firstTriangle = static_cast<std::uint32_t>(triangles_.size());
    nodes_[index].triangleCount = static_cast<std::uint32_t>(count);
    for (std::size_t t = begin; t < end; ++t) triangles_.push_back(source[order[t]]);
    return index;
  }
  const glm::dvec3 extentM = centroidMaxM - centroidMinM;
  const int axis = extentM.x >= extentM.y && extentM.x >= extentM.z ? 0 : (extentM.y >= extentM.z ? 1 : 2);
  const std::size_t middle = begin + count / 2;
  const auto orderAt = [&](std::size_t position) { return order.begin() + static_cast<std::ptrdiff_t>(position); };
  std::nth_element(orderAt(begin), orderAt(middle), orderAt(end), [&](std::uint32_t first, std::uint32_t second) {
    return centroid(source[first])[axis] < centroid(source[second])[axis];
  });
  build(order, begin, middle, source);
  const std::uint32_t secondChild = build(order, middle, end, source);
  nodes_[index].secondChild = secondChild;
  return index;
}

double WindingNumber::at(const glm::dvec3& pointM) const {
  double solidAngleSum = 0;
  std::uint32_t pending[maxTreeDepth];
  int pendingCount = 0;
  pending[pendingCount++] = 0;
  while (pendingCount > 0) {
    const std::uint32_t nodeIndex = pending[--pendingCount];
    const Node& node = nodes_[nodeIndex];
    const glm::dvec3 d = node.expansionCenterM - pointM;
    const double distanceSquaredM2 = glm::dot(d, d);
    if (distanceSquaredM2 > node.farDistanceSquaredM2) {
      solidAngleSum += farFieldSolidAngle(node, d, distanceSquaredM2);
    } else if (node.triangleCount > 0) {
      for (std::uint32_t t = node.firstTriangle; t < node.firstTriangle + node.triangleCount; ++t) {
        solidAngleSum += solidAngle(triangles_[t], pointM);
      }
    } else {
      pending[pendingCount++] = node.secondChild;
      pending[pendingCount++] = nodeIndex + 1;
    }
  }
  return solidAngleSum / (4 * pi);
}

// Barill 2018: a cluster subtends Ω = Σ_t ∫_t n_t · f(x − p) dA with f(d) = d / |d|³, the gradient of the
// Laplace Green's function up to sign and 4π. With d = c̃ − p and e = x − c̃, Taylor-expand f(d + e) to second
// order, f_i + J_ij e_j + ½ H_ijk e_j e_k, where
//   J_ij  = δ_ij / |d|³ − 3 d_i d_j / |d|⁵,
//   H_ijk = −3 (δ_ij d_k + δ_ik d_j + δ_jk d_i) / |d|⁵ + 15 d_i d_j d_k / |d|⁷,
// and integrate term by term against the cluster's moments.
double WindingNumber::farFieldSolidAngle(const Node& node, const glm::dvec3& d, double distanceSquaredM2) {
  const double inverseCube = 1 / (distanceSquaredM2 * std::sqrt(distanceSquaredM2));
  const double inverseFifth = inverseCube / distanceSquaredM2;
  const double dipoleTerm = glm::dot(node.areaNormalM2, d) * inverseCube;

  const glm::dmat3& first = node.firstMomentM3;  // S_ij = Σ_t a_t n_i (x_t − c̃)_j
  const double firstTrace = first[0][0] + first[1][1] + first[2][2];
  const double firstOrderTerm = firstTrace * inverseCube - 3 * glm::dot(d, first * d) * inverseFifth;

  // T_ijk = secondMomentM4[i]_jk, symmetric in j and k: the δ_ij and δ_ik parts of H give the same sum.
  double deltaIJ = 0;
  double deltaJK = 0;
  double dddTerm = 0;
  for (int i = 0; i < 3; ++i) {
    const glm::dmat3& second = node.secondMomentM4[i];
    const glm::dvec3 secondTimesD = second * d;
    deltaIJ += secondTimesD[i];
    deltaJK += d[i] * (second[0][0] + second[1][1] + second[2][2]);
    dddTerm += d[i] * glm::dot(d, secondTimesD);
  }
  const double secondOrderTerm =
      0.5 * (-3 * (2 * deltaIJ + deltaJK) * inverseFifth + 15 * dddTerm * inverseFifth / distanceSquaredM2);
  return dipoleTerm + firstOrderTerm + secondOrderTerm;
}

double WindingNumber::exactAt(const glm::dvec3& pointM) const {
  double solidAngleSum = 0;
  for (const Triangle& triangle : triangles_) solidAngleSum += solidAngle(triangle, pointM);
  return solidAngleSum / (4 * pi);
}

bool WindingNumber::inside(const glm::dvec3& pointM) const { return std::abs(at(pointM)) >= 0.5; }

}  // namespace firn::voxelizer
