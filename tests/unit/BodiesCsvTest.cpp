// bodies.csv without a GPU (docs/command-line.md, bodies.csv): its rows as written, the quaternion's sign kept
// continuous per object, a resumed run's kept rows, and values that are never written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/BodiesCsv.h"
#include "support/TestFiles.h"

namespace {

namespace fs = std::filesystem;
using firn::test::fileBytes;
using firn::test::freshDirectory;

firn::ObjectFrameRow row(int frame, const std::string& object, const glm::dquat& orientation) {
  firn::ObjectFrameRow r;
  r.frame = frame;
  r.timeS = frame / 10.0;
  r.object = object;
  r.kind = "collider";
  r.positionM = {0.1, 0.2, 0.3};
  r.orientation = orientation;
  r.velocityMPerS = {1, 0, -1};
  r.angularVelocityRadPerS = {0, 0.5, 0};
  return r;
}

std::string header() { return std::string(firn::BodiesCsvWriter::header()) + "\n"; }

// Each value as the shortest text that reads back as the same double ("0.1", not "0.10000000000000001").
TEST(BodiesCsv, RowsHoldTheFrameTheObjectAndItsPose) {
  const fs::path path = freshDirectory("bodies_rows") / "bodies.csv";
  {
    firn::BodiesCsvWriter bodies(path);
    bodies.write({row(1, "colliders[1]", {0.5, 0.5, 0.5, 0.5})});
  }
  EXPECT_EQ(fileBytes(path),
            header() + "1,0.1,colliders[1],collider,0.1,0.2,0.3,0.5,0.5,0.5,0.5,1,0,-1,0,0.5,0,0,0,0,0\n");
}

// q and −q are the same turn; a DCC that interpolates the components would turn the long way between a frame's q
// and the next frame's −q. Each object's sign follows its own previous row, whatever the other objects'.
TEST(BodiesCsv, QuaternionKeepsTheSignOfTheObjectsPreviousRow) {
  const fs::path path = freshDirectory("bodies_sign") / "bodies.csv";
  {
    firn::BodiesCsvWriter bodies(path);
    bodies.write({row(0, "a", {0.6, 0, 0.8, 0}), row(0, "b", {-0.6, 0, 0.8, 0})});
    bodies.write({row(1, "a", {-0.6, 0, -0.8, 0}), row(1, "b", {0.6, 0, -0.8, 0})});
  }
  const std::string text = fileBytes(path);
  EXPECT_NE(text.find("\n1,0.1,a,collider,0.1,0.2,0.3,0.6,0,0.8,0,"), std::string::npos) << text;
  EXPECT_NE(text.find("\n1,0.1,b,collider,0.1,0.2,0.3,-0.6,0,0.8,0,"), std::string::npos) << text;
}

// Resumed at frame 2, the rows of frames 0 and 1 stay byte for byte, those from 2 on are dropped (the run writes
// them again), and the sign of frame 2's quaternion follows frame 1's kept row.
TEST(BodiesCsv, ResumeKeepsTheEarlierRowsAndTheirSigns) {
  const fs::path path = freshDirectory("bodies_resume") / "bodies.csv";
  {
    firn::BodiesCsvWriter bodies(path);
    for (int frame = 0; frame < 4; ++frame) bodies.write({row(frame, "rigid_bodies[0]", {-0.6, 0, 0.8, 0})});
  }
  const std::string written = fileBytes(path);
  const std::string kept = written.substr(0, written.find("\n2,") + 1);
  std::ofstream(path, std::ios::app) << "4,0.4,rigid_bod";  // a row cut short by a killed run
  {
    firn::BodiesCsvWriter bodies(path, 2);
    EXPECT_EQ(fileBytes(path), kept);
    bodies.write({row(2, "rigid_bodies[0]", {0.6, 0, -0.8, 0})});
  }
  EXPECT_EQ(fileBytes(path), written.substr(0, written.find("\n3,") + 1));
}

TEST(BodiesCsv, NonFiniteValuesAreNeverWritten) {
  const fs::path path = freshDirectory("bodies_nan") / "bodies.csv";
  firn::BodiesCsvWriter bodies(path);
  firn::ObjectFrameRow bad = row(3, "rigid_bodies[0]", {1, 0, 0, 0});
  bad.angularVelocityRadPerS.z = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(bodies.write({bad}), std::invalid_argument);
  bad = row(3, "rigid_bodies[0]", {1, 0, 0, std::numeric_limits<double>::infinity()});
  EXPECT_THROW(bodies.write({bad}), std::invalid_argument);
  EXPECT_EQ(fileBytes(path), header());
}

}  // namespace
