#pragma once
// Frames to video with the `ffmpeg` program, when it is installed (Firn does not link a video encoder).
#include <filesystem>
#include <optional>

namespace firn {

// The ffmpeg executable found on PATH, if any.
std::optional<std::filesystem::path> findFfmpeg();

// Encodes `framesDir`/frame_0000.png … frame_<frameCount − 1>.png at `frameRateHz` into `videoPath` (H.264,
// yuv420p, so that browsers and players take it); frames a longer earlier run left in the folder are not
// used. Throws InputError if ffmpeg is missing or fails; ffmpeg's own message goes to stderr.
void assembleVideo(const std::filesystem::path& framesDir, int frameCount, double frameRateHz,
                   const std::filesystem::path& videoPath);

}  // namespace firn
