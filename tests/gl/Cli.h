#pragma once
// Running the `firn` executable as a user would, for the command-line tests.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>
#include "support/TestFiles.h"

namespace firn::test {

struct Result {
  int exitCode;
  std::string output;  // stdout and stderr
};

// `environment` is prepended to the command line ("FIRN_EGL_DEVICE=99", or a wrapper such as kOnXvfb).
inline Result runFirn(const std::string& arguments, const std::string& environment = "") {
  const std::string command = environment + " " + FIRN_EXECUTABLE + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return {-1, "popen failed"};
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// The wrapper that runs a command on a virtual X server (xvfb-run) and exits with the command's own status, for the
// viewer's tests: tests/support/on-xvfb.sh says why xvfb-run's own status will not do.
inline const std::string kOnXvfb = FIRN_SOURCE_DIR "/tests/support/on-xvfb.sh";

// A ball of 0.2 m radius at 8 particles per cell (cells 0.05 m): about 8 · (4π/3) 4³ = 2,145 particles (2,167
// sampled), two frames of 20 steps: a scene that starts and runs in a moment.
inline const char* const kBallScene = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 2 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.2, "material": "snow" } ] })";

// The lines of `output` that start with `prefix`, without it.
inline std::vector<std::string> linesAfter(const std::string& output, const std::string& prefix) {
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) lines.push_back(line.substr(prefix.size()));
  }
  return lines;
}

inline std::filesystem::path writeScene(const std::filesystem::path& directory, const std::string& name,
                                        const std::string& json) {
  const std::filesystem::path path = directory / name;
  std::ofstream(path) << json;
  return path;
}

// A CSV file's rows (RFC 4180): a quoted cell may hold commas, and "" stands for a quote.
inline std::vector<std::vector<std::string>> readCsv(const std::filesystem::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cells.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = !quoted;
      } else if (c == ',' && !quoted) {
        cells.emplace_back();
      } else {
        cells.back() += c;
      }
    }
    rows.push_back(cells);
  }
  return rows;
}

// A CSV file read by column name (stats.csv, bodies.csv): its header, and its rows after it.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string text(std::size_t row, const std::string& column) const {
    const auto found = std::find(header.begin(), header.end(), column);
    if (found == header.end()) throw std::runtime_error("the table has no column " + column);
    return rows.at(row).at(std::size_t(found - header.begin()));
  }
  double at(std::size_t row, const std::string& column) const { return std::stod(text(row, column)); }
};

inline Table readTable(const std::filesystem::path& path) {
  const std::vector<std::vector<std::string>> csv = readCsv(path);
  if (csv.empty()) return {};
  return {csv.front(), {csv.begin() + 1, csv.end()}};
}

// Whether `program` is an executable on the PATH.
inline bool onPath(const std::string& program) {
  return std::system(("command -v " + program + " >/dev/null 2>&1").c_str()) == 0;
}

}  // namespace firn::test
