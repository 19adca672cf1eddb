#include "gl/Buffer.h"

#include <utility>

namespace firn::gl {

Buffer::Buffer(std::size_t bytes, const void* data) : bytes_(bytes) {
  glGenBuffers(1, &id_);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  // The storage is whole 32-bit words, so that zero()'s clear of words covers every byte: GL refuses to clear R32UI
  // over a size that is not a multiple of 4 (GL_INVALID_VALUE) and leaves the buffer as it was.
  const std::size_t storageBytes = (bytes + 3) / 4 * 4;
  if (data == nullptr || storageBytes == bytes) {
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(storageBytes), data, GL_DYNAMIC_DRAW);
  } else {
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(storageBytes), nullptr, GL_DYNAMIC_DRAW);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(bytes), data);
  }
  if (data == nullptr) zero();
}

Buffer::~Buffer() {
  if (id_ != 0) glDeleteBuffers(1, &id_);
}

Buffer::Buffer(Buffer&& other) noexcept
    : id_(std::exchange(other.id_, 0)), bytes_(std::exchange(other.bytes_, 0)) {}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteBuffers(1, &id_);
    id_ = std::exchange(other.id_, 0);
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

Buffer&& Buffer::labelled(const char* label) && {
  this->label(label);
  return std::move(*this);
}

void Buffer::label(const char* label) const {
  if (id_ != 0) glObjectLabel(GL_BUFFER, id_, -1, label);
}

void Buffer::bindStorage(GLuint binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_); }

void Buffer::bindUniform(GLuint binding) const { glBindBufferBase(GL_UNIFORM_BUFFER, binding, id_); }

void Buffer::upload(std::size_t offsetBytes, std::size_t bytes, const void* data) {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offsetBytes), static_cast<GLsizeiptr>(bytes), data);
}

void Buffer::download(std::size_t offsetBytes, std::size_t bytes, void* out) const {
  // Readbacks follow compute writes: make those writes visible to buffer reads first.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offsetBytes), static_cast<GLsizeiptr>(bytes), out);
}

void Buffer::copyFrom(const Buffer& source, std::size_t bytes, std::size_t fromBytes, std::size_t toBytes) {
  glBindBuffer(GL_COPY_READ_BUFFER, source.id_);
  glBindBuffer(GL_COPY_WRITE_BUFFER, id_);
  glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, static_cast<GLintptr>(fromBytes),
                      static_cast<GLintptr>(toBytes), static_cast<GLsizeiptr>(bytes));
}

void Buffer::zero() {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  // NVIDIA's driver (580, H100) lands the clear after a glBufferSubData issued right after it, so an upload into a
  // fresh buffer was lost (docs/platform.md): wait for the clear. Buffers are cleared when allocated, not per step.
  glFinish();
}

GLuint Buffer::release() {
  bytes_ = 0;
  return std::exchange(id_, 0);
}

}  // namespace firn::gl
