#include "run/RunRecord.h"

#include "io/AtomicFile.h"
#include "sim/SceneUpload.h"

namespace firn {

namespace {

nlohmann::ordered_json timings(const std::vector<std::pair<TransferShape, double>>& timed) {
  nlohmann::ordered_json times = nlohmann::ordered_json::object();
  for (const auto& [shape, ms] : timed) times[transferShapeName(shape)] = ms;
  return times;
}

}  // namespace

RunRecord::RunRecord(std::filesystem::path path, const Scene& scene, const std::vector<std::string>& commandLine,
                     const gl::ContextInfo& device, int processes)
    : path_(std::move(path)) {
  json_["firn_version"] = FIRN_VERSION;
  json_["command_line"] = commandLine;
  json_["scene"] = {{"file", sceneFileName(scene)}, {"name", scene.name}, {"fingerprint", nullptr}};
  json_["device"] = {{"renderer", device.renderer},
                     {"vendor", device.vendor},
                     {"gl_version", device.version},
                     {"platform", device.platform}};
  json_["processes"] = processes;
  json_["transfers"] = nullptr;
  json_["frames"] = {{"first", 0}, {"last", 0}, {"frame_rate_hz", scene.time.frameRateHz}};
  json_["steps"] = 0;
  json_["particles"] = 0;
  json_["wall_s"] = 0.0;
  json_["exit"] = {{"status", nullptr}, {"message", "running"}};
}

void RunRecord::setSceneFingerprint(std::uint64_t fingerprint) {
  json_["scene"]["fingerprint"] = fingerprintHex(fingerprint);
}

void RunRecord::setTransfers(const std::optional<TransferShapeChoice>& choice) {
  if (!choice) {
    json_["transfers"] = {{"description", transfersLine(choice)}};
    return;
  }
  nlohmann::ordered_json transfers = {{"description", choice->describe()},
                                      {"shape", transferShapeName(choice->shape)},
                                      {"forced", choice->forced},
                                      {"timed_on_particles", choice->particles},
                                      {"ms_per_transfer", timings(choice->msPerTransfer)}};
  if (!choice->msPerProduct.empty()) {
    transfers["product_shape"] = transferShapeName(choice->productShape);
    transfers["ms_per_product"] = timings(choice->msPerProduct);
  }
  json_["transfers"] = std::move(transfers);
}

void RunRecord::setProgress(int firstFrame, int lastFrame, std::uint64_t steps, std::size_t particles, double wallS) {
  json_["frames"]["first"] = firstFrame;
  json_["frames"]["last"] = lastFrame;
  json_["steps"] = steps;
  json_["particles"] = particles;
  json_["wall_s"] = wallS;
}

void RunRecord::setExit(int status, const std::string& message) {
  json_["exit"] = {{"status", status}, {"message", message}};
}

void RunRecord::write() const { writeFileAtomically(path_, json_.dump(2) + "\n", "run record"); }

}  // namespace firn
