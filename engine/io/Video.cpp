#include "io/Video.h"

#include <sstream>
#include <string>
#include <vector>

#include "Error.h"
#include "io/ExternalProgram.h"

namespace firn {

std::optional<std::filesystem::path> findFfmpeg() { return findProgram("ffmpeg"); }

void assembleVideo(const std::filesystem::path& framesDir, int frameCount, double frameRateHz,
                   const std::filesystem::path& videoPath) {
  const std::optional<std::filesystem::path> ffmpeg = findFfmpeg();
  if (!ffmpeg) {
    throw InputError(videoPath.string() + ": --mp4 needs the ffmpeg program, which is not on the PATH "
                                          "(Debian: apt-get install ffmpeg); the PNG frames are in " + framesDir.string());
  }
  std::ostringstream rate;
  rate.precision(17);
  rate << frameRateHz;
  const std::vector<std::string> arguments = {
      ffmpeg->string(), "-hide_banner", "-loglevel", "error", "-y", "-framerate", rate.str(),
      "-i", (framesDir / "frame_%04d.png").string(), "-frames:v", std::to_string(frameCount),
      // H.264 in yuv420p needs even dimensions.
      "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "18",
      videoPath.string()};
  const std::string failure = runProgram(arguments);
  if (!failure.empty()) {
    throw InputError(videoPath.string() + ": " + failure + " (its message, if any, is above); the PNG frames are in " +
                     framesDir.string());
  }
}

}  // namespace firn
