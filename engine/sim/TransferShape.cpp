#include "sim/TransferShape.h"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "Error.h"
#include "gpu/GpuLayout.h"

namespace firn {

namespace {

constexpr int kBlockGroupSizes[] = {64, 128, 256};

std::string milliseconds(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, ms < 10 ? "%.3g ms" : "%.1f ms", ms);
  return text;
}

// Every shape, in the order a choice lists them.
std::vector<TransferShape> everyShape() {
  std::vector<TransferShape> shapes = {{TransferShape::Kind::Tiles, 0}};
  for (const int size : kBlockGroupSizes) shapes.push_back({TransferShape::Kind::Blocks, size});
  return shapes;
}

}  // namespace

std::string transferShapeName(const TransferShape& shape) {
  return shape.kind == TransferShape::Kind::Tiles ? "tiles" : "blocks-" + std::to_string(shape.groupSize);
}

std::size_t blockTableDispatch(const TransferShape& shape) {
  return shape.kind == TransferShape::Kind::Tiles ? offsetof(gpu::BlockTableHeader, tileDispatch)
                                                  : offsetof(gpu::BlockTableHeader, blockDispatch);
}

std::vector<TransferShape> transferShapes(const Scene& scene) {
  if (scene.solver.atomics == Atomics::FixedPoint) return everyShape();
  return {{TransferShape::Kind::Tiles, 0}};
}

std::vector<std::string> transferShapeNames() {
  std::vector<std::string> names = {"tiles", "blocks"};
  for (const TransferShape& shape : everyShape()) {
    if (shape.kind == TransferShape::Kind::Blocks) names.push_back(transferShapeName(shape));
  }
  return names;
}

TransferShapeCandidates transferShapeCandidates(const Scene& scene, const std::string& names) {
  if (names.empty()) return {transferShapes(scene), false};
  std::vector<TransferShape> named;
  for (const TransferShape& shape : everyShape()) {
    const bool all = names == "blocks" && shape.kind == TransferShape::Kind::Blocks;
    if (all || transferShapeName(shape) == names) named.push_back(shape);
  }
  if (named.empty()) {
    std::string known;
    for (const std::string& name : transferShapeNames()) known += (known.empty() ? "" : ", ") + name;
    throw InputError("transfer shape: expected one of " + known + " (got \"" + names + "\")");
  }
  const std::vector<TransferShape> possible = transferShapes(scene);
  if (std::find(possible.begin(), possible.end(), named.front()) == possible.end()) {
    throw InputError("transfer shape " + names +
                     ": blocks sum in fixed point only, and the scene's solver.atomics is \"float\"; use tiles");
  }
  return {named, true};
}

gl::ShaderOptions shapeShaderOptions(gl::ShaderOptions options, const TransferShape& shape) {
  if (shape.kind == TransferShape::Kind::Blocks) {
    options.defines.emplace_back("FIRN_P2G_BLOCK_GROUP_SIZE", std::to_string(shape.groupSize));
  }
  return options;
}

std::vector<double> fastestOfRounds(std::size_t candidates, int rounds,
                                    const std::function<double(std::size_t)>& timeOne) {
  std::vector<double> fastestMs(candidates, std::numeric_limits<double>::infinity());
  for (int round = 0; round <= rounds; ++round) {
    for (std::size_t i = 0; i < candidates; ++i) {
      const double ms = timeOne(i);
      if (round > 0) fastestMs[i] = std::min(fastestMs[i], ms);
    }
  }
  return fastestMs;
}

std::size_t fastestEntry(const std::vector<std::pair<TransferShape, double>>& timed) {
  return std::size_t(std::min_element(timed.begin(), timed.end(),
                                      [](const auto& a, const auto& b) { return a.second < b.second; }) -
                     timed.begin());
}

namespace {

// "blocks-128, 3.10x faster than tiles (0.71 ms against 2.2 ms": the chosen of `timed` against the fastest other.
std::string againstRunnerUp(const TransferShape& chosen, const std::vector<std::pair<TransferShape, double>>& timed) {
  double chosenMs = 0;
  const std::pair<TransferShape, double>* runnerUp = nullptr;
  for (const auto& entry : timed) {
    if (entry.first == chosen) {
      chosenMs = entry.second;
    } else if (runnerUp == nullptr || entry.second < runnerUp->second) {
      runnerUp = &entry;
    }
  }
  char ratio[32];
  std::snprintf(ratio, sizeof ratio, "%.2f", runnerUp->second / std::max(chosenMs, 1e-9));
  return transferShapeName(chosen) + ", " + ratio + "x faster than " + transferShapeName(runnerUp->first) + " (" +
         milliseconds(chosenMs) + " against " + milliseconds(runnerUp->second);
}

}  // namespace

std::string TransferShapeChoice::describe() const {
  const std::string name = transferShapeName(shape);
  const std::string asked = forced ? std::string(", as the run was asked") : std::string();
  if (msPerTransfer.size() < 2) return "P2G by " + name + (forced ? asked : ", the only shape for this scene");
  std::string line = "P2G by " + againstRunnerUp(shape, msPerTransfer) + ", timed on " + std::to_string(particles) +
                     " particles)";
  if (msPerProduct.size() >= 2) line += "; Hessian product by " + againstRunnerUp(productShape, msPerProduct) + ")";
  return line + asked;
}

std::string transfersLine(const std::optional<TransferShapeChoice>& choice) {
  if (!choice) return "transfers: P2G's shape is timed at the first step with particles";
  return "transfers: " + choice->describe();
}

}  // namespace firn
