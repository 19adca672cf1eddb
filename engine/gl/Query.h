#pragma once
// Move-only owner of a GL_TIME_ELAPSED query: GPU time of the commands between begin() and end().
#include <cstdint>

#include "gl/GL.h"

namespace firn::gl {

class TimerQuery {
 public:
  TimerQuery();
  ~TimerQuery();
  TimerQuery(TimerQuery&& other) noexcept;
  TimerQuery& operator=(TimerQuery&& other) noexcept;
  TimerQuery(const TimerQuery&) = delete;
  TimerQuery& operator=(const TimerQuery&) = delete;

  void begin();
  void end();
  // Waits for the result.
  std::uint64_t elapsedNanoseconds() const;
  GLuint id() const { return id_; }

 private:
  GLuint id_ = 0;
};

}  // namespace firn::gl
