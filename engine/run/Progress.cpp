#include "run/Progress.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "Error.h"

namespace firn {
namespace {

double nowS() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// A terminal's line is rewritten at most this often: more is flicker nobody reads.
constexpr double kTerminalIntervalS = 0.25;
// A log's lines: often enough to show that the work goes on, seldom enough that an hour's run writes 720 lines.
constexpr double kDefaultLogIntervalS = 5;

}  // namespace

double progressLogIntervalS() {
  const char* text = std::getenv("FIRN_PROGRESS_INTERVAL_S");
  if (text == nullptr) return kDefaultLogIntervalS;
  char* end = nullptr;
  errno = 0;
  const double seconds = std::strtod(text, &end);
  if (*text == '\0' || *end != '\0' || errno == ERANGE || !(seconds > 0) || !std::isfinite(seconds)) {
    throw InputError(std::string("FIRN_PROGRESS_INTERVAL_S: expected the seconds between progress lines, a number "
                                 "greater than 0 (got \"") + text + "\")");
  }
  return seconds;
}

ProgressLine::ProgressLine(std::FILE* stream, double quietS)
    : stream_(stream), terminal_(isatty(fileno(stream)) != 0), quietS_(quietS),
      intervalS_(terminal_ ? kTerminalIntervalS : progressLogIntervalS()), startS_(nowS()) {}

ProgressLine::~ProgressLine() {
  if (shown_ && terminal_) std::fprintf(stream_, "\n");
}

void ProgressLine::show(const std::string& text, bool last) {
  const double now = nowS();
  const bool due = terminal_ ? now - startS_ >= quietS_ && now - shownS_ >= intervalS_
                             : now - std::max(startS_, shownS_) >= intervalS_;
  if (!due && !(last && terminal_)) return;
  shownS_ = now;
  shown_ = true;
  if (terminal_) {
    std::fprintf(stream_, "\r%s   ", text.c_str());
  } else {
    std::fprintf(stream_, "%s\n", text.c_str());
  }
  std::fflush(stream_);
}

void ProgressLine::showFraction(const std::string& prefix, double fraction) {
  const double now = nowS();
  if (prefix != prefix_) {
    prefix_ = prefix;
    startS_ = now;
  }
  const double elapsedS = now - startS_;
  const int etaS = fraction > 0 ? static_cast<int>(elapsedS / fraction * (1 - fraction) + 0.5) : 0;
  char text[32];
  std::snprintf(text, sizeof text, " %3.0f%%  ETA %d:%02d", 100 * std::clamp(fraction, 0.0, 1.0), etaS / 60, etaS % 60);
  show(prefix + text);
}

}  // namespace firn
