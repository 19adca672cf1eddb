#include "gl/BufferTexture.h"

#include <utility>

namespace firn::gl {

BufferTexture::BufferTexture(const std::vector<float>& values)
    : buffer_(values.empty() ? Buffer(sizeof(float)) : Buffer::fromVector(values)) {
  glGenTextures(1, &id_);
  glBindTexture(GL_TEXTURE_BUFFER, id_);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_R32F, buffer_.id());
  glBindTexture(GL_TEXTURE_BUFFER, 0);
}

BufferTexture::~BufferTexture() {
  if (id_ != 0) glDeleteTextures(1, &id_);
}

BufferTexture::BufferTexture(BufferTexture&& other) noexcept
    : buffer_(std::move(other.buffer_)), id_(std::exchange(other.id_, 0)) {}

BufferTexture& BufferTexture::operator=(BufferTexture&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteTextures(1, &id_);
    buffer_ = std::move(other.buffer_);
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}

void BufferTexture::bind(GLuint textureUnit) const {
  glActiveTexture(GL_TEXTURE0 + textureUnit);
  glBindTexture(GL_TEXTURE_BUFFER, id_);
}

}  // namespace firn::gl
