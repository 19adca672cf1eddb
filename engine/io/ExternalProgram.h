#pragma once
// Programs Firn runs when they are installed and it does not link (ffmpeg for video, gnuplot for plots).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace firn {

// The executable `name` found on PATH, if any.
std::optional<std::filesystem::path> findProgram(const std::string& name);

// Runs `arguments` (the program first) and waits for it, without a shell, so that paths with spaces or quotes need no
// escaping. Returns "" on success, else why it failed: it could not be started, exited with a status, or was killed.
std::string runProgram(const std::vector<std::string>& arguments);

}  // namespace firn
