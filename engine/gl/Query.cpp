#include "gl/Query.h"

#include <utility>

namespace firn::gl {

TimerQuery::TimerQuery() { glGenQueries(1, &id_); }

TimerQuery::~TimerQuery() {
  if (id_ != 0) glDeleteQueries(1, &id_);
}

TimerQuery::TimerQuery(TimerQuery&& other) noexcept : id_(std::exchange(other.id_, 0)) {}

TimerQuery& TimerQuery::operator=(TimerQuery&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteQueries(1, &id_);
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}

void TimerQuery::begin() { glBeginQuery(GL_TIME_ELAPSED, id_); }

void TimerQuery::end() { glEndQuery(GL_TIME_ELAPSED); }

std::uint64_t TimerQuery::elapsedNanoseconds() const {
  GLuint64 nanoseconds = 0;
  glGetQueryObjectui64v(id_, GL_QUERY_RESULT, &nanoseconds);
  return nanoseconds;
}

}  // namespace firn::gl
