#pragma once
// bodies.csv: where each moving object of a scene (a rigid body, a collider that moves) is at each frame, one row per
// frame and object, for a DCC to replay beside the snow (docs/command-line.md, bodies.csv). The run finds the poses
// (run/HeadlessRun.cpp); this file formats them.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "io/FrameCsv.h"

namespace firn {

// A point p of the object's own frame is at positionM + orientation · p.
struct ObjectFrameRow {
  int frame = 0;
  double timeS = 0;
  std::string object;  // "colliders[1]", "rigid_bodies[0]": no comma, no quote
  std::string kind;    // "collider" or "rigid_body"
  glm::dvec3 positionM{0.0};
  glm::dquat orientation{1, 0, 0, 0};      // unit
  glm::dvec3 velocityMPerS{0.0};           // of the frame's origin
  glm::dvec3 angularVelocityRadPerS{0.0};  // world axes
  glm::dvec3 forceN{0.0};  // the snow's mean force on the object over the steps since the previous frame
  double workJ = 0;        // the work the object did on the snow since the start (the energy audit's)
};

class BodiesCsvWriter {
 public:
  // Starts the file afresh: the header alone. Throws InputError naming the file if it cannot be written.
  explicit BodiesCsvWriter(const std::filesystem::path& path);
  // Continues the file of a run resumed at `firstFrame`, as stats.csv is continued (io/FrameCsv.h): the rows of the
  // frames before it are kept, the rest dropped. Throws InputError as FrameCsv does.
  BodiesCsvWriter(const std::filesystem::path& path, int firstFrame);

  // Writes one frame's rows and flushes them. q and −q are the same turn; each row's quaternion is the one of the
  // two nearer its object's previous row (a positive dot product), so that a DCC interpolating the components
  // between frames turns the short way. A value that is not finite, or a name with a comma or quote, is
  // std::invalid_argument (a defect: the run checks the poses first).
  void write(const std::vector<ObjectFrameRow>& rows);

  static const char* header();

 private:
  FrameCsv file_;
  std::map<std::string, glm::dquat> lastOrientation_;  // by object, for the sign of its next row's quaternion
};

}  // namespace firn
