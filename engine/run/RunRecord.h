#pragma once
// run.json, beside stats.csv (docs/command-line.md, run.json): what describes a run rather than a frame — Firn's
// version, the command line, the device, the scene and its fingerprint, the transfers' shape and the times that chose
// it, how far the run got, and how it ended: its exit status and message (null and "running" while it runs). Written
// when the run starts and again when it ends, each time whole (through a temporary file and a rename).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gl/Context.h"
#include "scene/Scene.h"
#include "sim/TransferShape.h"

namespace firn {

class RunRecord {
 public:
  RunRecord(std::filesystem::path path, const Scene& scene, const std::vector<std::string>& commandLine,
            const gl::ContextInfo& device, int processes);

  void setSceneFingerprint(std::uint64_t fingerprint);
  void setTransfers(const std::optional<TransferShapeChoice>& choice);
  // How far the run got: its frames (the first, 0 or a checkpoint's, and the last written), steps and particles.
  void setProgress(int firstFrame, int lastFrame, std::uint64_t steps, std::size_t particles, double wallS);
  // How it ended: the exit status of the command-line contract and its message (empty for success).
  void setExit(int status, const std::string& message);

  // Writes the file. Throws InputError naming it if it cannot be written.
  void write() const;

 private:
  std::filesystem::path path_;
  nlohmann::ordered_json json_;
};

}  // namespace firn
