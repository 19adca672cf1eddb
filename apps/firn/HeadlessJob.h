#pragma once
// `firn run` of a saved scene, started from the scene editor's window as a process of its own (this executable,
// `run SCENE --out DIR`): the usual outputs, written while the user goes on editing. Its output is read as it comes,
// without waiting: its progress lines (every half second: FIRN_PROGRESS_INTERVAL_S) give the frame it is at.
#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace firn {

class HeadlessJob {
 public:
  // Starts the run; throws std::runtime_error when the process cannot be started.
  HeadlessJob(const std::filesystem::path& scene, const std::filesystem::path& outputDir);
  // Stops a run still going (SIGTERM) and waits for it.
  ~HeadlessJob();
  HeadlessJob(const HeadlessJob&) = delete;
  HeadlessJob& operator=(const HeadlessJob&) = delete;

  // Reads what the run has written since, and notes its end. Never waits.
  void poll();
  // Waits for the run to end, reading its output.
  void wait();
  void stop();

  bool running() const { return !exitCode_.has_value(); }
  // The run's exit status once it has ended (docs/command-line.md, Exit codes; 128 + the signal that ended it;
  // 255 where it could not be known).
  std::optional<int> exitCode() const { return exitCode_; }
  // Its lines so far, and the fraction of its frames done (from its progress lines; 1 once it wrote them all).
  const std::vector<std::string>& lines() const { return lines_; }
  double fraction() const { return fraction_; }
  const std::filesystem::path& outputDir() const { return outputDir_; }

 private:
  void take(const std::string& line);
  // Reads what the pipe holds now, line by line; closes it at its end.
  void readOutput();

  std::filesystem::path outputDir_;
  pid_t pid_ = -1;
  int output_ = -1;  // the read end of the run's stdout and stderr
  std::string partial_;
  std::vector<std::string> lines_;
  double fraction_ = 0;
  std::optional<int> exitCode_;
};

}  // namespace firn
