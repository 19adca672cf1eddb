#pragma once
// Move-only owner of a GL buffer object.
#include <cstddef>
#include <vector>

#include "gl/GL.h"

namespace firn::gl {

class Buffer {
 public:
  Buffer() = default;
  // Allocates `bytes` (zero-filled when `data` is null) for use as a shader storage buffer.
  explicit Buffer(std::size_t bytes, const void* data = nullptr);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  template <typename T>
  static Buffer fromVector(const std::vector<T>& values) {
    return Buffer(values.size() * sizeof(T), values.data());
  }

  GLuint id() const { return id_; }
  std::size_t bytes() const { return bytes_; }
  explicit operator bool() const { return id_ != 0; }

  // Names the buffer in GPU debuggers (glObjectLabel); returns it, for `Buffer(bytes).labelled("…")`.
  Buffer&& labelled(const char* label) &&;
  void label(const char* label) const;

  void bindStorage(GLuint binding) const;
  void bindUniform(GLuint binding) const;
  void upload(std::size_t offsetBytes, std::size_t bytes, const void* data);
  void download(std::size_t offsetBytes, std::size_t bytes, void* out) const;
  void zero();
  // Copies `bytes` of `source` from `fromBytes` into this buffer at `toBytes`, on the GPU (glCopyBufferSubData);
  // `source` may be this buffer, with ranges that do not overlap.
  void copyFrom(const Buffer& source, std::size_t bytes, std::size_t fromBytes = 0, std::size_t toBytes = 0);

  template <typename T>
  std::vector<T> read(std::size_t count, std::size_t firstElement = 0) const {
    std::vector<T> values(count);
    download(firstElement * sizeof(T), count * sizeof(T), values.data());
    return values;
  }

  // Gives up ownership: the caller deletes the returned name.
  GLuint release();

 private:
  GLuint id_ = 0;
  std::size_t bytes_ = 0;
};

}  // namespace firn::gl
