#include "io/Video.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "Error.h"

extern char** environ;

namespace firn {

std::optional<std::filesystem::path> findFfmpeg() {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return std::nullopt;
  std::stringstream directories(path);
  std::string directory;
  while (std::getline(directories, directory, ':')) {
    if (directory.empty()) continue;
    const std::filesystem::path candidate = std::filesystem::path(directory) / "ffmpeg";
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return std::nullopt;
}

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
  std::vector<char*> argv;
  for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  // posix_spawn, not system(): no shell, so paths with spaces or quotes need no escaping.
  pid_t child = 0;
  const int spawnError = posix_spawn(&child, argv[0], nullptr, nullptr, argv.data(), environ);
  if (spawnError != 0) {
    throw InputError(videoPath.string() + ": could not start " + ffmpeg->string() + " (" + std::strerror(spawnError) + ")");
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) throw InputError(videoPath.string() + ": lost track of ffmpeg (" + std::strerror(errno) + ")");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw InputError(videoPath.string() + ": ffmpeg failed (" +
                     (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                        : std::string("killed by a signal")) +
                     "; its message is above); the PNG frames are in " + framesDir.string());
  }
}

}  // namespace firn
