#include "gl/PassTimer.h"

#include <algorithm>

#include "gl/Debug.h"

namespace firn::gl {

void PassTimer::setEnabled(bool enabled) {
  enabled_ = enabled;
  times_.clear();
}

void PassTimer::begin() {
  if (!enabled_) return;
  glFinish();
  query_.begin();
  wallStart_ = std::chrono::steady_clock::now();
}

void PassTimer::end(const std::string& pass) {
  checkPass(pass.c_str());
  if (!enabled_) return;
  query_.end();
  glFinish();
  const double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wallStart_).count();
  auto entry = std::find_if(times_.begin(), times_.end(), [&](const PassTime& time) { return time.pass == pass; });
  if (entry == times_.end()) entry = times_.insert(times_.end(), PassTime{pass});
  entry->totalMs += double(query_.elapsedNanoseconds()) * 1e-6;
  entry->totalWallMs += wallMs;
  ++entry->dispatches;
}

double msToFinish(const std::function<void()>& work) {
  glFinish();
  const auto start = std::chrono::steady_clock::now();
  work();
  glFinish();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace firn::gl
