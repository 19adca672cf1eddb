// The slabs a run over several processes splits the domain into (mpi/Slabs.h): which layer a particle is in, and
// slabs drawn for equal particle counts, each at least a layer thick.
#include <gtest/gtest.h>

#include <vector>

#include "Error.h"
#include "mpi/Slabs.h"
#include "scene/Scene.h"

namespace firn::mpi {
namespace {

Scene sceneOfCells(int cellsZ, Kernel kernel) {
  Scene scene = defaultScene();
  scene.grid.originM = glm::dvec3(0.0);
  scene.grid.cellSizeM = 0.1;
  scene.grid.cells = glm::ivec3(8, 8, cellsZ);
  scene.solver.kernel = kernel;
  return scene;
}

TEST(Slabs, LayerIsTheStencilBaseNodesBlock) {
  // 32 cells: 33 nodes, 9 layers of 4 nodes. Quadratic: base node floor(z/h − 0.5); cubic: floor(z/h) − 1.
  const Slabs quadratic(sceneOfCells(32, Kernel::Quadratic), 2);
  EXPECT_EQ(quadratic.layers(), 9);
  EXPECT_EQ(quadratic.layerOf({0, 0, 0.449f}), 0);  // base node 3
  EXPECT_EQ(quadratic.layerOf({0, 0, 0.451f}), 1);  // base node 4
  const Slabs cubic(sceneOfCells(32, Kernel::Cubic), 2);
  EXPECT_EQ(cubic.layerOf({0, 0, 0.49f}), 0);       // base node 3
  EXPECT_EQ(cubic.layerOf({0, 0, 0.51f}), 1);       // base node 4
  EXPECT_EQ(cubic.layerOf({0, 0, -1.0f}), 0);       // outside: clamped
  EXPECT_EQ(cubic.layerOf({0, 0, 99.0f}), 8);
}

TEST(Slabs, EqualThicknessUntilBalanced) {
  const Slabs slabs(sceneOfCells(32, Kernel::Quadratic), 3);  // 9 layers
  EXPECT_EQ(slabs.firstLayer(0), 0);
  EXPECT_EQ(slabs.firstLayer(1), 3);
  EXPECT_EQ(slabs.firstLayer(2), 6);
  EXPECT_EQ(slabs.firstLayer(3), 9);
  EXPECT_EQ(slabs.ownerOfLayer(2), 0);
  EXPECT_EQ(slabs.ownerOfLayer(3), 1);
  EXPECT_EQ(slabs.ownerOfLayer(8), 2);
}

TEST(Slabs, BalancedSlabsHoldEqualCountsAndALayerEach) {
  Slabs slabs(sceneOfCells(32, Kernel::Quadratic), 3);
  // 300 particles: 100 in layer 1, 100 in layer 2, 100 in layer 7 → a slab ends after each of the first two, at
  // the first layer where a third of them lie below.
  slabs.balance({0, 100, 100, 0, 0, 0, 0, 100, 0});
  EXPECT_EQ(slabs.describe(), "0–1 | 2–2 | 3–8");
  // Everything in one layer: the slabs still hold a layer each, the last ones past it.
  slabs.balance({0, 0, 0, 0, 300, 0, 0, 0, 0});
  EXPECT_EQ(slabs.firstLayer(1), 5);
  EXPECT_EQ(slabs.firstLayer(2), 6);
  slabs.balance({0, 0, 0, 0, 0, 0, 0, 0, 300});
  EXPECT_EQ(slabs.describe(), "0–6 | 7–7 | 8–8");
}

TEST(Slabs, RefusesMoreRanksThanLayers) {
  // 8 cells: 9 nodes, 3 layers.
  EXPECT_NO_THROW(Slabs(sceneOfCells(8, Kernel::Quadratic), 3));
  EXPECT_THROW(Slabs(sceneOfCells(8, Kernel::Quadratic), 4), InputError);
}

}  // namespace
}  // namespace firn::mpi
