#pragma once
// Move-only owners of what drawing needs beyond buffers and programs: 2-D textures, framebuffers (a colour
// texture and an optional depth texture) and vertex array objects.
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "gl/GL.h"

namespace firn::gl {

class Buffer;

// An immutable-size 2-D texture with one mip level and linear, edge-clamped sampling.
class Texture2D {
 public:
  Texture2D() = default;
  // `internalFormat` is a sized format: GL_RGBA8, GL_R16F, GL_DEPTH_COMPONENT32F …
  Texture2D(glm::ivec2 sizePx, GLenum internalFormat);
  ~Texture2D();
  Texture2D(Texture2D&& other) noexcept;
  Texture2D& operator=(Texture2D&& other) noexcept;
  Texture2D(const Texture2D&) = delete;
  Texture2D& operator=(const Texture2D&) = delete;

  GLuint id() const { return id_; }
  glm::ivec2 size() const { return size_; }
  explicit operator bool() const { return id_ != 0; }
  void bind(GLuint textureUnit) const;

  // Gives up ownership: the caller deletes the returned name.
  GLuint release();

 private:
  GLuint id_ = 0;
  glm::ivec2 size_{0};
};

// A framebuffer object with its own attachments: one colour texture and, optionally, a 32-bit float depth
// texture. It has no release(): it owns its attachments, and handing over the framebuffer name alone would
// leave it pointing at deleted textures.
class Framebuffer {
 public:
  Framebuffer() = default;
  // Throws GLError if the driver reports the combination incomplete.
  Framebuffer(glm::ivec2 sizePx, GLenum colorFormat = GL_RGBA8, bool withDepth = true);
  ~Framebuffer();
  Framebuffer(Framebuffer&& other) noexcept;
  Framebuffer& operator=(Framebuffer&& other) noexcept;
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  glm::ivec2 size() const { return color_.size(); }
  const Texture2D& color() const { return color_; }

  // Binds it for drawing (GL_DRAW_FRAMEBUFFER).
  void bind() const;
  // The framebuffer bound for drawing now (0: the default one), to rebind after drawing elsewhere.
  static GLuint boundForDrawing();

  // The colour attachment as tightly packed 8-bit RGBA, top row first (GL's rows start at the bottom).
  // Waits for drawing to finish. Leaves the read framebuffer binding as it found it.
  std::vector<std::uint8_t> readColorRgba8() const;

 private:
  GLuint id_ = 0;
  Texture2D color_;
  Texture2D depth_;
};

// The colour of the framebuffer bound for reading (a Framebuffer, or after glBindFramebuffer(GL_FRAMEBUFFER, 0)
// a window's back buffer), rows (0, 0)–sizePx, as tightly packed 8-bit RGBA, top row first (GL's rows start
// at the bottom). Waits for drawing to finish.
std::vector<std::uint8_t> readRgba8TopRowFirst(glm::ivec2 sizePx);

// A vertex array object: the vertex attribute layout of a draw. Core profile draws only with one bound, even
// when the vertex shader reads no attributes (it then stays empty).
class VertexArray {
 public:
  VertexArray();
  ~VertexArray();
  VertexArray(VertexArray&& other) noexcept;
  VertexArray& operator=(VertexArray&& other) noexcept;
  VertexArray(const VertexArray&) = delete;
  VertexArray& operator=(const VertexArray&) = delete;

  GLuint id() const { return id_; }
  void bind() const;

  // Feeds attribute `location` with `components` floats per vertex from `buffer`, `strideBytes` apart,
  // starting at `offsetBytes`. The array keeps a reference to the buffer: it must outlive the array's use.
  void setFloatAttribute(GLuint location, const Buffer& buffer, int components, std::size_t strideBytes,
                         std::size_t offsetBytes);
  // Draws with glDrawElements take their indices from `buffer` (GL_ELEMENT_ARRAY_BUFFER, part of the array's
  // state), which must outlive the array's use.
  void setIndexBuffer(const Buffer& buffer);

  GLuint release();

 private:
  GLuint id_ = 0;
};

}  // namespace firn::gl
