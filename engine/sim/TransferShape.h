#pragma once
// The shape of particle to grid, and of the semi-implicit solve's Hessian product (docs/numerics.md, Transfers). Both
// shapes add the same quantized contributions and integer sums do not depend on the order, so they write the same
// bytes; which one runs is chosen by timing each (P2G, and the product on its own) on the run's own scene and
// device, never by the scene file.
//   tiles   an invocation per tile of base nodes sums its particles in private accumulators (p2g.comp,
//           solver_product.comp): built for CPU renderers, which run an invocation's private arrays as vector
//           registers
//   blocks  a work group per block, an invocation per particle, the block's region summed in shared memory
//           (p2g_block.comp, solver_product_block.comp), in groups of 64, 128 or 256 invocations: built for GPUs
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gl/ShaderLibrary.h"
#include "scene/Scene.h"

namespace firn {

struct TransferShape {
  enum class Kind { Tiles, Blocks };
  Kind kind = Kind::Tiles;
  int groupSize = 0;  // blocks: invocations per work group

  bool operator==(const TransferShape& other) const { return kind == other.kind && groupSize == other.groupSize; }
};

// "tiles", "blocks-64", "blocks-128", "blocks-256": the names a run is given its shapes by and the tables print.
std::string transferShapeName(const TransferShape& shape);

// Where in the block table a pass of this shape finds its indirect dispatch: tiles take the transfers' tiles, blocks
// a work group per active block (the step's own dispatches, which the solve's iterations copy and may empty).
std::size_t blockTableDispatch(const TransferShape& shape);

// The shapes a scene's P2G can take: tiles, and with fixed-point sums blocks of each group size (float sums depend
// on their order, so a float scene keeps the tiles: its bytes stay the same from run to run on one device).
std::vector<TransferShape> transferShapes(const Scene& scene);

// The shapes a run times before it keeps the fastest: every shape the scene can take (`names` empty), or those
// `names` names (`firn run --transfer-shape`, benchmarks and tests): "tiles", "blocks" (each group size), or one of
// "blocks-64", "blocks-128", "blocks-256". Throws InputError for another name, or for blocks with float sums.
struct TransferShapeCandidates {
  std::vector<TransferShape> shapes;
  bool forced = false;  // named rather than every shape
};
TransferShapeCandidates transferShapeCandidates(const Scene& scene, const std::string& names);

// Every name transferShapeCandidates takes, in its order: "tiles", "blocks", "blocks-64", ….
std::vector<std::string> transferShapeNames();

// A pass's shader options in `shape`: blocks take their group size (FIRN_P2G_BLOCK_GROUP_SIZE).
gl::ShaderOptions shapeShaderOptions(gl::ShaderOptions options, const TransferShape& shape);

// Each of `candidates` timed once untimed (a driver may build a program's code at its first dispatch) and then
// `rounds` times, round after round; `timeOne(i)` runs candidate i once and returns its milliseconds. Each
// candidate's fastest round: a shared machine's noise only ever adds time.
std::vector<double> fastestOfRounds(std::size_t candidates, int rounds,
                                    const std::function<double(std::size_t)>& timeOne);
// The entry with the least time (the first of equals).
std::size_t fastestEntry(const std::vector<std::pair<TransferShape, double>>& timed);

// The shape a run takes, and the P2G times that chose it (ms; empty when there was one candidate); in a
// semi-implicit run also the Hessian product's, timed on its own (it runs a few to tens of times a step, and its
// shapes need not win where P2G's do).
struct TransferShapeChoice {
  TransferShape shape;
  bool forced = false;  // the run was given the candidates by name
  std::vector<std::pair<TransferShape, double>> msPerTransfer;
  std::size_t particles = 0;  // the particles they were timed on
  TransferShape productShape;  // the Hessian product's (semi-implicit runs)
  std::vector<std::pair<TransferShape, double>> msPerProduct;  // empty when untimed

  // One line for a run's log and firn info: "P2G by blocks-128, 3.10x faster than tiles (0.71 ms against 2.2 ms,
  // timed on 91,897 particles)", and "; Hessian product by …, … faster than …" when the product was timed.
  std::string describe() const;
};

// A run's line for its log's header and stats.csv's comment: "transfers: " and the choice's description, or that
// P2G's shape is timed at the first step with particles where the run starts with none.
std::string transfersLine(const std::optional<TransferShapeChoice>& choice);

}  // namespace firn
