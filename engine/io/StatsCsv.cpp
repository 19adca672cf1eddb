#include "io/StatsCsv.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

#include "Error.h"
#include "io/AtomicFile.h"
#include "io/InputFile.h"

namespace firn {

const char* StatsCsvWriter::header() {
  return "frame,time_s,steps,particles,mass_kg,momentum_x,momentum_y,momentum_z,kinetic_energy_j,wall_ms,"
         "center_of_mass_x,center_of_mass_y,center_of_mass_z,mean_plastic_j,particles_at_walls,active_blocks,"
         "solver_iterations,solver_residual";
}

StatsCsvWriter::StatsCsvWriter(const std::filesystem::path& path) : path_(path) {
  start(std::string(header()) + '\n');
}

StatsCsvWriter::StatsCsvWriter(const std::filesystem::path& path, int firstFrame) : path_(path) {
  std::string rows = std::string(header()) + '\n';
  std::error_code error;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, error))) {
    start(rows);
    return;
  }
  requireRegularFile(path, "stats file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot read stats file (" + std::strerror(errno) + ")");
  std::string line;
  std::getline(in, line);
  if (line != header()) {
    throw InputError(path.string() + ": its header is not the one this version of Firn writes, so its rows before "
                     "frame " + std::to_string(firstFrame) + " cannot be kept; move it away to resume without them");
  }
  for (int lineNumber = 2; std::getline(in, line); ++lineNumber) {
    // A last line without its line break is a row cut short by a run that was killed while writing it.
    if (in.eof()) break;
    int frame = 0;
    const auto [end, parseError] = std::from_chars(line.data(), line.data() + line.size(), frame);
    if (parseError != std::errc() || end == line.data() + line.size() || *end != ',') {
      throw InputError(path.string() + ": line " + std::to_string(lineNumber) +
                       ": no frame number, so the rows before frame " + std::to_string(firstFrame) +
                       " cannot be kept; move it away to resume without them");
    }
    if (frame < firstFrame) rows += line + '\n';
  }
  if (in.bad()) throw InputError(path.string() + ": cannot read stats file (" + std::strerror(errno) + ")");
  in.close();
  start(rows);
}

void StatsCsvWriter::start(const std::string& rows) {
  writeFileAtomically(path_, rows, "stats file");
  out_.open(path_, std::ios::app);
  if (!out_) throw InputError(path_.string() + ": cannot write stats file (" + std::strerror(errno) + ")");
}

void StatsCsvWriter::write(const FrameStats& s) {
  const double values[] = {s.massKg,           s.momentumKgMPerS.x, s.momentumKgMPerS.y, s.momentumKgMPerS.z,
                           s.kineticEnergyJ,   s.wallMs,            s.centerOfMassM.x,   s.centerOfMassM.y,
                           s.centerOfMassM.z,  s.meanPlasticJ,      s.timeS,             s.solverResidual};
  for (double value : values) {
    if (!std::isfinite(value)) throw std::invalid_argument("stats row for frame " + std::to_string(s.frame) + " is not finite");
  }
  char row[512];
  std::snprintf(row, sizeof row, "%d,%.9g,%llu,%llu,%.9g,%.9g,%.9g,%.9g,%.9g,%.3f,%.9g,%.9g,%.9g,%.9g,%llu,%llu,%d,%.3g\n", s.frame,
                s.timeS, static_cast<unsigned long long>(s.steps), static_cast<unsigned long long>(s.particles),
                s.massKg, s.momentumKgMPerS.x, s.momentumKgMPerS.y, s.momentumKgMPerS.z, s.kineticEnergyJ, s.wallMs,
                s.centerOfMassM.x, s.centerOfMassM.y, s.centerOfMassM.z, s.meanPlasticJ,
                static_cast<unsigned long long>(s.particlesAtWalls), static_cast<unsigned long long>(s.activeBlocks),
                s.solverIterations, s.solverResidual);
  out_ << row;
  out_.flush();
  if (!out_) throw InputError(path_.string() + ": writing the stats failed (disk full?)");
}

}  // namespace firn
