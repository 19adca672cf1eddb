// The slabs a run over several processes splits the domain into (mpi/Slabs.h): which layer a particle is in, and
// slabs drawn for equal particle counts across the axis the particles span most, each at least a layer thick.
#include <gtest/gtest.h>

#include <vector>

#include "Error.h"
#include "mpi/Slabs.h"
#include "scene/Scene.h"

namespace firn::mpi {
namespace {

Scene sceneOfCells(glm::ivec3 cells, Kernel kernel) {
  Scene scene = defaultScene();
  scene.grid.originM = glm::dvec3(0.0);
  scene.grid.cellSizeM = 0.1;
  scene.grid.cells = cells;
  scene.solver.kernel = kernel;
  return scene;
}

// Counts with `perZ` along z and everything in layer 0 along x and y (a span of one layer).
LayerCounts alongZ(const Slabs& slabs, const std::vector<std::uint64_t>& perZ) {
  LayerCounts counts = slabs.emptyCounts();
  std::uint64_t total = 0;
  for (const std::uint64_t c : perZ) total += c;
  counts[0][0] = counts[1][0] = total;
  counts[2] = perZ;
  return counts;
}

TEST(Slabs, LayerIsTheStencilBaseNodesBlock) {
  // 32 cells: 33 nodes, 9 layers of 4 nodes. Quadratic: base node floor(z/h − 0.5); cubic: floor(z/h) − 1.
  const Slabs quadratic(sceneOfCells({8, 8, 32}, Kernel::Quadratic), 2);
  EXPECT_EQ(quadratic.layers(), 9);
  EXPECT_EQ(quadratic.layerOf({0, 0, 0.449f}, 2), 0);  // base node 3
  EXPECT_EQ(quadratic.layerOf({0, 0, 0.451f}, 2), 1);  // base node 4
  const Slabs cubic(sceneOfCells({8, 8, 32}, Kernel::Cubic), 2);
  EXPECT_EQ(cubic.layerOf({0, 0, 0.49f}, 2), 0);       // base node 3
  EXPECT_EQ(cubic.layerOf({0, 0, 0.51f}, 2), 1);       // base node 4
  EXPECT_EQ(cubic.layerOf({0, 0, -1.0f}, 2), 0);       // outside: clamped
  EXPECT_EQ(cubic.layerOf({0, 0, 99.0f}, 2), 8);
  EXPECT_EQ(cubic.layerOf({0.51f, 0, 0}, 0), 1);       // along x
}

TEST(Slabs, EqualThicknessAcrossZUntilBalanced) {
  const Slabs slabs(sceneOfCells({8, 8, 32}, Kernel::Quadratic), 3);  // 9 layers
  EXPECT_EQ(slabs.axis(), 2);
  EXPECT_EQ(slabs.describe(), "z: 0–2 | 3–5 | 6–8");
  EXPECT_EQ(slabs.ownerOfLayer(2), 0);
  EXPECT_EQ(slabs.ownerOfLayer(3), 1);
  EXPECT_EQ(slabs.ownerOfLayer(8), 2);
}

TEST(Slabs, BalancedSlabsHoldEqualCountsAndALayerEach) {
  Slabs slabs(sceneOfCells({8, 8, 32}, Kernel::Quadratic), 3);
  // 300 particles: 100 in layer 1, 100 in layer 2, 100 in layer 7 → a slab ends after each of the first two, where
  // exactly a third and two thirds of them lie below.
  slabs.balance(alongZ(slabs, {0, 100, 100, 0, 0, 0, 0, 100, 0}));
  EXPECT_EQ(slabs.describe(), "z: 0–1 | 2–2 | 3–8");
  // Everything in one layer: the slabs still hold a layer each, the boundary nearest a third below it (no particles)
  // rather than above it (all of them).
  slabs.balance(alongZ(slabs, {0, 0, 0, 0, 300, 0, 0, 0, 0}));
  EXPECT_EQ(slabs.describe(), "z: 0–3 | 4–4 | 5–8");
  slabs.balance(alongZ(slabs, {0, 0, 0, 0, 0, 0, 0, 0, 300}));
  EXPECT_EQ(slabs.describe(), "z: 0–6 | 7–7 | 8–8");
}

TEST(Slabs, CutAcrossTheAxisTheParticlesSpanMost) {
  Slabs slabs(sceneOfCells({32, 8, 16}, Kernel::Quadratic), 2);  // 9, 3 and 5 layers
  LayerCounts counts = slabs.emptyCounts();
  counts[0] = {0, 10, 10, 10, 10, 10, 10, 0, 0};  // six layers along x
  counts[1] = {30, 30, 0};
  counts[2] = {0, 20, 20, 20, 0};                  // three along z
  slabs.balance(counts);
  EXPECT_EQ(slabs.axis(), 0);
  EXPECT_EQ(slabs.describe(), "x: 0–3 | 4–8");
  EXPECT_EQ(slabs.ownerOf({1.55f, 0.2f, 0.2f}), 0);  // base node 15 along x: layer 3
  EXPECT_EQ(slabs.ownerOf({1.66f, 0.2f, 0.2f}), 1);  // base node 16: layer 4
}

TEST(Slabs, RefusesMoreRanksThanLayersAlongEveryAxis) {
  // 8 cells: 9 nodes, 3 layers along each axis.
  EXPECT_NO_THROW(Slabs(sceneOfCells({8, 8, 8}, Kernel::Quadratic), 3));
  EXPECT_THROW(Slabs(sceneOfCells({8, 8, 8}, Kernel::Quadratic), 4), InputError);
  // z too thin, x has room: the slabs go across x.
  EXPECT_EQ(Slabs(sceneOfCells({32, 8, 8}, Kernel::Quadratic), 4).axis(), 0);
}

}  // namespace
}  // namespace firn::mpi
