#pragma once
// Move-only owner of a buffer texture: a buffer's floats read by texelFetch from a samplerBuffer, which, unlike a
// storage block, does not count against a shader's storage blocks (docs/platform.md).
#include <cstddef>
#include <vector>

#include "gl/Buffer.h"
#include "gl/GL.h"

namespace firn::gl {

class BufferTexture {
 public:
  BufferTexture() = default;
  // One GL_R32F texel per value; at least one, so that the texture is always complete.
  explicit BufferTexture(const std::vector<float>& values);
  ~BufferTexture();
  BufferTexture(BufferTexture&& other) noexcept;
  BufferTexture& operator=(BufferTexture&& other) noexcept;
  BufferTexture(const BufferTexture&) = delete;
  BufferTexture& operator=(const BufferTexture&) = delete;

  explicit operator bool() const { return id_ != 0; }
  std::size_t bytes() const { return buffer_.bytes(); }
  void bind(GLuint textureUnit) const;

 private:
  Buffer buffer_;
  GLuint id_ = 0;
};

}  // namespace firn::gl
