// `firn bench` as a user runs it, at the test-only --tiny sizes: every table is written with its header and
// finite numbers, and bad options exit with 2 before anything is measured.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "Cli.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::readCsv;
using firn::test::Result;
using firn::test::runFirn;

// Whether the whole cell is a number (strtod reads "nan" and "inf" too, which is what must not be there).
bool isNumber(const std::string& cell, double& value) {
  if (cell.empty()) return false;
  char* end = nullptr;
  value = std::strtod(cell.c_str(), &end);
  return end == cell.c_str() + cell.size();
}

TEST(BenchCli, TinyRunWritesEveryTableWithFiniteNumbers) {
  const fs::path out = freshDirectory("bench_tiny") / "tables";
  const Result result = runFirn("bench --tiny --repeats 2 --no-plots --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;

  const std::map<std::string, std::vector<std::string>> leadingColumns = {
      {"particles.csv",
       {"series", "kernel", "atomics", "transfer_shape", "particles", "grid_cells", "grid_dims", "cell_size_m",
        "particles_per_cell"}},
      {"grid.csv", {"atomics", "transfer_shape", "grid_cells", "grid_dims", "particles", "active_nodes"}},
      {"domain.csv", {"grid_cells", "grid_dims", "transfer_shape", "particles", "active_blocks", "active_nodes", "pool_blocks", "pool_mib",
                      "block_map_mib"}},
      {"passes.csv",
       {"atomics", "transfer_shape", "integrator", "kernel", "pass", "gpu_ms", "wall_ms", "share_of_step",
        "dispatches_per_step"}},
      {"p2g_atomics.csv", {"atomics", "transfer_shape", "p2g_ms", "p2g_gpu_ms", "mass_max_rel_error", "mass_rms_rel_error",
                           "momentum_max_rel_error", "momentum_rms_rel_error"}},
      {"tradeoff.csv", {"configuration", "integrator", "implicit_ratio", "kernel", "transfer", "flip_ratio",
                        "atomics", "transfer_shape", "dt_s", "dt_fraction", "particles_per_cell", "cell_size_m", "particles", "steps",
                        "ms_per_step", "ms_per_simulated_second", "period_s", "error"}},
      {"stiff.csv", {"configuration", "youngs_modulus_pa", "integrator", "dt_s", "dt_over_elastic_bound",
                     "tolerance", "max_iterations", "particles", "simulated_s", "steps", "ms_per_step",
                     "ms_per_simulated_second", "cost_over_explicit", "mean_iterations"}},
      {"surface.csv", {"series", "particles", "resolution", "smoothing", "grid_nodes", "grid_mib", "vertices",
                       "triangles", "repeats", "surface_ms"}},
  };
  for (const auto& [file, columns] : leadingColumns) {
    const auto rows = readCsv(out / file);
    ASSERT_GE(rows.size(), 2u) << file << ": no rows";
    for (std::size_t i = 0; i < columns.size(); ++i) EXPECT_EQ(rows[0].at(i), columns[i]) << file;
    EXPECT_EQ(rows[0].back(), "renderer") << file;
    for (std::size_t r = 1; r < rows.size(); ++r) {
      ASSERT_EQ(rows[r].size(), rows[0].size()) << file << " row " << r;
      for (std::size_t c = 0; c < rows[r].size(); ++c) {
        double value = 0;
        if (isNumber(rows[r][c], value)) {
          EXPECT_TRUE(std::isfinite(value)) << file << " row " << r << " " << rows[0][c];
        }
        EXPECT_EQ(rows[r][c].find("nan"), std::string::npos) << file << " row " << r << " " << rows[0][c];
      }
    }
  }
  // Every configuration of the tiny sizes runs on llvmpipe: each row says "ok" and has its time.
  for (const std::string file :
       {"particles.csv", "grid.csv", "domain.csv", "tradeoff.csv", "stiff.csv", "surface.csv"}) {
    const auto rows = readCsv(out / file);
    std::size_t status = 0, time = 0;
    for (std::size_t c = 0; c < rows[0].size(); ++c) {
      if (rows[0][c] == "status") status = c;
      if (rows[0][c] == "ms_per_step") time = c;
    }
    for (std::size_t r = 1; r < rows.size(); ++r) {
      EXPECT_EQ(rows[r][status], "ok") << file << " row " << r;
      double ms = 0;
      EXPECT_TRUE(isNumber(rows[r][time], ms) && ms > 0) << file << " row " << r;
    }
  }
  // The tables of the step time fixed point in both P2G shapes, tiles and blocks (sim/TransferShape.h).
  for (const std::string file : {"particles.csv", "grid.csv", "passes.csv", "p2g_atomics.csv"}) {
    const auto rows = readCsv(out / file);
    const std::size_t atomics = file == "particles.csv" ? 2 : 0, shape = atomics + 1;  // particles.csv: series, kernel first
    bool tiles = false, blocks = false;
    for (std::size_t r = 1; r < rows.size(); ++r) {
      if (rows[r][atomics] != "fixed") continue;
      tiles = tiles || rows[r][shape] == "tiles";
      blocks = blocks || rows[r][shape].rfind("blocks-", 0) == 0;
    }
    EXPECT_TRUE(tiles && blocks) << file << ": fixed point in tiles and in blocks";
  }
  for (const std::string file : {"machine.txt", "summary.txt"}) EXPECT_TRUE(fs::is_regular_file(out / file)) << file;
  EXPECT_NE(result.output.find("particles: exponent"), std::string::npos) << result.output;
  // The whole run's time is said before the first table starts, and each table's progress as it ends.
  const std::size_t estimate = result.output.find("firn bench: estimated ");
  const std::size_t firstTable = result.output.find("firn bench: table 1 of 8, particles");
  EXPECT_TRUE(estimate != std::string::npos && firstTable != std::string::npos && estimate < firstTable)
      << result.output;
  EXPECT_NE(result.output.find("firn bench: surface took "), std::string::npos) << result.output;
}

TEST(BenchCli, BadOptionsExitWithTwo) {
  const fs::path directory = freshDirectory("bench_bad");
  const Result noParent = runFirn("bench --tiny --out " + (directory / "missing" / "tables").string());
  EXPECT_EQ(noParent.exitCode, 2) << noParent.output;
  EXPECT_NE(noParent.output.find("does not exist"), std::string::npos) << noParent.output;

  const Result noAssets =
      runFirn("bench --tiny --only particles --out " + (directory / "out").string() + " --assets " + directory.string());
  EXPECT_EQ(noAssets.exitCode, 2) << noAssets.output;
  EXPECT_NE(noAssets.output.find("bunny.obj"), std::string::npos) << noAssets.output;
  EXPECT_NE(noAssets.output.find("--assets"), std::string::npos) << noAssets.output;

  const Result badTable = runFirn("bench --tiny --only meshes --out " + (directory / "out").string());
  EXPECT_EQ(badTable.exitCode, 2) << badTable.output;
}

}  // namespace
