#pragma once
// Progress of long work (sampling, a run's frames, voxelizing) on a stream. On a terminal, one line rewritten in
// place ("\r…") a few times a second. Anywhere else (a log file, CI, a render farm) a whole line every
// progressLogIntervalS() seconds, so that a log shows the work going on and holds no carriage returns.
#include <cstdio>
#include <string>

namespace firn {

// Seconds between progress lines on a stream that is not a terminal: FIRN_PROGRESS_INTERVAL_S where set (a number
// > 0, else InputError naming it), otherwise 5.
double progressLogIntervalS();

class ProgressLine {
 public:
  // Whether `stream` is a terminal decides the style. `quietS`: nothing is shown on a terminal for work that takes
  // less (in a log, the first line comes after one interval).
  explicit ProgressLine(std::FILE* stream, double quietS = 1.0);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // Shows `text` when a line is due. `last`: on a terminal, shown whatever the time, so the final state stays.
  void show(const std::string& text, bool last = false);
  // "<prefix> 45%  ETA 0:12", the time counted from the first call with this prefix.
  void showFraction(const std::string& prefix, double fraction);

 private:
  std::FILE* stream_;
  bool terminal_;
  double quietS_;
  double intervalS_;
  std::string prefix_;
  double startS_;
  double shownS_ = -1;
  bool shown_ = false;
};

}  // namespace firn
