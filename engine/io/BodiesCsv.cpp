#include "io/BodiesCsv.h"

#include <cmath>
#include <cstdlib>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/Text.h"

namespace firn {

namespace {

// The cells of a kept row, split at its commas (no cell of bodies.csv holds one).
std::vector<std::string> cellsOf(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char c : line) {
    if (c == ',') {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

}  // namespace

const char* BodiesCsvWriter::header() {
  return "frame,time_s,object,kind,x_m,y_m,z_m,qw,qx,qy,qz,vx_m_per_s,vy_m_per_s,vz_m_per_s,wx_rad_per_s,"
         "wy_rad_per_s,wz_rad_per_s,fx_n,fy_n,fz_n,work_j";
}

BodiesCsvWriter::BodiesCsvWriter(const std::filesystem::path& path) : file_(path, header(), "bodies file") {}

BodiesCsvWriter::BodiesCsvWriter(const std::filesystem::path& path, int firstFrame)
    : file_(path, header(), "bodies file", firstFrame) {
  // The kept rows' last quaternion of each object sets the sign of its next, as in a run never interrupted.
  const std::string& kept = file_.keptRows();
  for (std::size_t start = 0; start < kept.size();) {
    const std::size_t end = kept.find('\n', start);
    const std::vector<std::string> cells = cellsOf(kept.substr(start, end - start));
    start = end + 1;
    if (cells.size() != 21) continue;  // a row this version would not write: no sign to keep
    glm::dquat q;
    q.w = std::strtod(cells[7].c_str(), nullptr);
    q.x = std::strtod(cells[8].c_str(), nullptr);
    q.y = std::strtod(cells[9].c_str(), nullptr);
    q.z = std::strtod(cells[10].c_str(), nullptr);
    lastOrientation_[cells[2]] = q;
  }
}

void BodiesCsvWriter::write(const std::vector<ObjectFrameRow>& rows) {
  // Nothing of a frame whose rows cannot all be written is kept, the signs included.
  std::map<std::string, glm::dquat> orientations = lastOrientation_;
  std::string text;
  for (const ObjectFrameRow& row : rows) {
    if (row.object.find_first_of(",\"\n") != std::string::npos || row.kind.find_first_of(",\"\n") != std::string::npos) {
      throw std::invalid_argument("bodies row for frame " + std::to_string(row.frame) + " names its object \"" +
                                  row.object + "\" with a character CSV would have to quote");
    }
    glm::dquat q = row.orientation;
    const auto last = orientations.find(row.object);
    if (last != orientations.end() && glm::dot(q, last->second) < 0) q = -q;
    const double values[] = {row.timeS,           row.positionM.x,     row.positionM.y,
                             row.positionM.z,     q.w,                 q.x,
                             q.y,                 q.z,                 row.velocityMPerS.x,
                             row.velocityMPerS.y, row.velocityMPerS.z, row.angularVelocityRadPerS.x,
                             row.angularVelocityRadPerS.y, row.angularVelocityRadPerS.z,
                             row.forceN.x,        row.forceN.y,        row.forceN.z,
                             row.workJ};
    for (double value : values) {
      if (!std::isfinite(value)) {
        throw std::invalid_argument("bodies row of " + row.object + " for frame " + std::to_string(row.frame) +
                                    " is not finite");
      }
    }
    orientations[row.object] = q;
    // The shortest text that reads back as the same double: a keyframe's pose reads as the scene gives it. −0 (a
    // quaternion's zero component with its sign turned) is written 0.
    text += std::to_string(row.frame) + ',' + formatNumber(row.timeS) + ',' + row.object + ',' + row.kind;
    for (std::size_t i = 1; i < std::size(values); ++i) text += ',' + formatNumber(values[i] == 0 ? 0.0 : values[i]);
    text += '\n';
  }
  file_.append(text);
  lastOrientation_ = std::move(orientations);
}

}  // namespace firn
