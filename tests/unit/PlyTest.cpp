#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "Error.h"
#include "io/Ply.h"

namespace {

std::filesystem::path temporaryPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("firn_ply_test_" + std::to_string(getpid()) + "_" + name);
}

firn::PointCache examplePoints() {
  firn::PointCache points;
  for (int i = 0; i < 100; ++i) {
    points.positionsM.emplace_back(0.01f * i, -1.5f + i, 1e-7f * i);
    points.velocitiesMPerS.emplace_back(-2.0f * i, 3.25f, 0.0f);
    points.massesKg.push_back(6.25e-3f);
    points.plasticJ.push_back(1.0f - 1e-3f * i);
  }
  return points;
}

// Binary little-endian floats round-trip bit for bit.
TEST(Ply, BinaryRoundTripIsExact) {
  const auto path = temporaryPath("roundtrip.ply");
  const firn::PointCache written = examplePoints();
  firn::writePly(path, written);
  const firn::PointCache read = firn::readPly(path);
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    EXPECT_EQ(read.positionsM[i], written.positionsM[i]);
    EXPECT_EQ(read.velocitiesMPerS[i], written.velocitiesMPerS[i]);
    EXPECT_EQ(read.massesKg[i], written.massesKg[i]);
    EXPECT_EQ(read.plasticJ[i], written.plasticJ[i]);
  }
  std::ifstream in(path, std::ios::binary);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "ply");
  std::filesystem::remove(path);
}

TEST(Ply, ReadsAsciiWithPositionsOnly) {
  const auto path = temporaryPath("ascii.ply");
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                         "property float z\nend_header\n1 2 3\n4.5 5 -6\n";
  const firn::PointCache read = firn::readPly(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read.positionsM[1], glm::vec3(4.5f, 5.0f, -6.0f));
  EXPECT_EQ(read.plasticJ[0], 1.0f);
  std::filesystem::remove(path);
}

TEST(Ply, NonFiniteValueIsNeverWritten) {
  const auto path = temporaryPath("nan.ply");
  firn::PointCache points = examplePoints();
  points.velocitiesMPerS[7].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(firn::writePly(path, points), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(Ply, TruncatedOrMissingFileIsBadInputNamingIt) {
  const auto path = temporaryPath("truncated.ply");
  firn::writePly(path, examplePoints());
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 10);
  try {
    firn::readPly(path);
    FAIL() << "expected InputError";
  } catch (const firn::InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path.string() + ": truncated"), std::string::npos) << error.what();
  }
  std::filesystem::remove(path);
  EXPECT_THROW(firn::readPly(temporaryPath("absent.ply")), firn::InputError);
}

// A header's vertex count is checked against the file's size before anything is allocated for it, so a
// corrupt count is bad input, not an allocation failure.
TEST(Ply, VertexCountBeyondTheFileIsBadInput) {
  const auto path = temporaryPath("huge.ply");
  for (const char* format : {"binary_little_endian", "ascii"}) {
    std::ofstream(path) << "ply\nformat " << format << " 1.0\nelement vertex 1000000000000000\nproperty float x\n"
                        << "property float y\nproperty float z\nend_header\n0 0 0\n";
    try {
      firn::readPly(path);
      ADD_FAILURE() << "expected InputError for " << format;
    } catch (const firn::InputError& error) {
      EXPECT_NE(std::string(error.what()).find("more than the file's"), std::string::npos) << error.what();
    }
  }
  std::filesystem::remove(path);
}

}  // namespace
