#pragma once
// The shape of the transfers, P2G and G2P (docs/numerics.md, "Transfers"). Both shapes add the same quantized
// contributions to the grid (integer sums do not depend on the order) and update each particle with the same code, so
// they write the same bytes; which one runs is chosen by timing both on the run's own scene and device, never by the
// scene file.
//   tiles   P2G: an invocation per tile of base nodes sums its particles in private accumulators (p2g.comp); G2P: an
//           invocation per particle (g2p.comp). Built for CPU renderers, which run an invocation's private arrays as
//           vector registers.
//   blocks  a work group per block and an invocation per particle, the block's region in shared memory: P2G sums it
//           there (p2g_block.comp), G2P reads it from there (g2p_block.comp); 64, 128 or 256 invocations per group.
//           Built for GPUs.
#include <optional>
#include <string>
#include <vector>

#include "scene/Scene.h"

namespace firn {

struct TransferShape {
  enum class Kind { Tiles, Blocks };
  Kind kind = Kind::Tiles;
  int groupSize = 0;  // blocks: invocations per work group

  bool operator==(const TransferShape& other) const { return kind == other.kind && groupSize == other.groupSize; }
};

// "tiles", "blocks-64", "blocks-128", "blocks-256": the names FIRN_TRANSFER_SHAPE takes and the tables print.
std::string transferShapeName(const TransferShape& shape);

// The shapes a scene's transfers can take: tiles, and with fixed-point sums blocks of each group size (float sums
// depend on their order, so a float scene keeps the tiles: its bytes stay the same from run to run on one device).
std::vector<TransferShape> transferShapes(const Scene& scene);

// The shapes a run times before it keeps the fastest: every shape the scene can take, or those FIRN_TRANSFER_SHAPE
// names (for benchmarks and tests): "tiles", "blocks" (each group size), or one of "blocks-64", "blocks-128",
// "blocks-256". Throws InputError for another name, or for blocks with float sums.
struct TransferShapeCandidates {
  std::vector<TransferShape> shapes;
  bool forced = false;  // FIRN_TRANSFER_SHAPE named them
};
TransferShapeCandidates transferShapeCandidates(const Scene& scene);

// The shape a run takes, and the times of its transfers (P2G and G2P, ms) that chose it; empty when there was one
// candidate.
struct TransferShapeChoice {
  TransferShape shape;
  bool forced = false;  // FIRN_TRANSFER_SHAPE named the candidates
  std::vector<std::pair<TransferShape, double>> msPerTransfer;

  // One line for a run's header and firn info: "transfers by blocks-128, 3.10x faster than tiles (P2G and G2P
  // 0.71 ms against 2.2 ms, timed on this scene)".
  std::string describe() const;
};

}  // namespace firn
