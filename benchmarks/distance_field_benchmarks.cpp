// Google Benchmark timing of a mesh collider's distance field bake (voxelizer/DistanceField.h): a torus of 1 m
// across, 100,000 triangles, at a spacing of 1/128 m with a margin of three spacings (a lattice of 135 × 135 × 46
// samples), and a 99,500-triangle UV sphere of 1 m diameter (135³ samples), on 1 and 2 threads. Wall time and the
// process's CPU time (all threads), in seconds.
//   build/release/benchmarks/firn_distance_field_benchmarks --benchmark_repetitions=3
#include <benchmark/benchmark.h>

#include "support/TestMeshes.h"
#include "voxelizer/DistanceField.h"

namespace {

constexpr double spacingM = 1.0 / 128;
constexpr double marginM = 3 * spacingM;

void Bake(benchmark::State& state, const firn::voxelizer::TriangleMesh& mesh) {
  const auto threads = unsigned(state.range(0));
  for (auto _ : state) {
    const firn::voxelizer::DistanceField field = firn::voxelizer::bakeDistanceField(mesh, spacingM, marginM, threads);
    benchmark::DoNotOptimize(field.distancesM.data());
    state.counters["samples"] = double(field.sampleCount());
  }
  state.counters["triangles"] = double(mesh.triangles.size());
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  // 2 · 500 · 100 triangles; ring and tube radii 0.35 m and 0.15 m: 1 m across, 0.3 m thick.
  static const firn::voxelizer::TriangleMesh torus = firn::test::torus(0.35, 0.15, 500, 100);
  // 2 · 250 · 199 = 99,500 triangles.
  static const firn::voxelizer::TriangleMesh sphere = firn::test::uvSphere(0.5, 200, 250);
  for (const auto& [name, mesh] : {std::pair{"Bake/torus100k", &torus}, std::pair{"Bake/sphere100k", &sphere}}) {
    benchmark::RegisterBenchmark(name, Bake, *mesh)
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kSecond)
        ->UseRealTime()
        ->MeasureProcessCPUTime()
        ->Iterations(1);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
