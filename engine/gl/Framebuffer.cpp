#include "gl/Framebuffer.h"

#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "Error.h"
#include "gl/Buffer.h"

namespace firn::gl {

Texture2D::Texture2D(glm::ivec2 sizePx, GLenum internalFormat) : size_(sizePx) {
  glGenTextures(1, &id_);
  glBindTexture(GL_TEXTURE_2D, id_);
  glTexStorage2D(GL_TEXTURE_2D, 1, internalFormat, sizePx.x, sizePx.y);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);
}

Texture2D::~Texture2D() {
  if (id_ != 0) glDeleteTextures(1, &id_);
}

Texture2D::Texture2D(Texture2D&& other) noexcept
    : id_(std::exchange(other.id_, 0)), size_(std::exchange(other.size_, glm::ivec2(0))) {}

Texture2D& Texture2D::operator=(Texture2D&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteTextures(1, &id_);
    id_ = std::exchange(other.id_, 0);
    size_ = std::exchange(other.size_, glm::ivec2(0));
  }
  return *this;
}

void Texture2D::bind(GLuint textureUnit) const {
  glActiveTexture(GL_TEXTURE0 + textureUnit);
  glBindTexture(GL_TEXTURE_2D, id_);
}

GLuint Texture2D::release() {
  size_ = glm::ivec2(0);
  return std::exchange(id_, 0);
}

Framebuffer::Framebuffer(glm::ivec2 sizePx, GLenum colorFormat, bool withDepth) : color_(sizePx, colorFormat) {
  if (withDepth) depth_ = Texture2D(sizePx, GL_DEPTH_COMPONENT32F);
  const GLuint previous = boundForDrawing();
  glGenFramebuffers(1, &id_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, id_);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_.id(), 0);
  if (depth_) glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth_.id(), 0);
  const GLenum status = glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, previous);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", status);
    throw GLError("framebuffer of " + std::to_string(sizePx.x) + "×" + std::to_string(sizePx.y) +
                  " pixels is incomplete (status " + code + ")");
  }
}

Framebuffer::~Framebuffer() {
  if (id_ != 0) glDeleteFramebuffers(1, &id_);
}

Framebuffer::Framebuffer(Framebuffer&& other) noexcept
    : id_(std::exchange(other.id_, 0)), color_(std::move(other.color_)), depth_(std::move(other.depth_)) {}

Framebuffer& Framebuffer::operator=(Framebuffer&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteFramebuffers(1, &id_);
    id_ = std::exchange(other.id_, 0);
    color_ = std::move(other.color_);
    depth_ = std::move(other.depth_);
  }
  return *this;
}

void Framebuffer::bind() const { glBindFramebuffer(GL_DRAW_FRAMEBUFFER, id_); }

GLuint Framebuffer::boundForDrawing() {
  GLint framebuffer = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  return static_cast<GLuint>(framebuffer);
}

std::vector<std::uint8_t> Framebuffer::readColorRgba8() const {
  GLint previousRead = 0;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &previousRead);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, id_);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  std::vector<std::uint8_t> pixels = readRgba8TopRowFirst(size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(previousRead));
  return pixels;
}

std::vector<std::uint8_t> readRgba8TopRowFirst(glm::ivec2 sizePx) {
  const std::size_t rowBytes = static_cast<std::size_t>(sizePx.x) * 4;
  std::vector<std::uint8_t> bottomUp(rowBytes * static_cast<std::size_t>(sizePx.y));
  GLint previousAlignment = 0;
  glGetIntegerv(GL_PACK_ALIGNMENT, &previousAlignment);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);  // rows tightly packed, whatever the width
  glReadPixels(0, 0, sizePx.x, sizePx.y, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
  glPixelStorei(GL_PACK_ALIGNMENT, previousAlignment);

  std::vector<std::uint8_t> topDown(bottomUp.size());
  for (int row = 0; row < sizePx.y; ++row) {
    std::memcpy(topDown.data() + static_cast<std::size_t>(row) * rowBytes,
                bottomUp.data() + static_cast<std::size_t>(sizePx.y - 1 - row) * rowBytes, rowBytes);
  }
  return topDown;
}

VertexArray::VertexArray() { glGenVertexArrays(1, &id_); }

VertexArray::~VertexArray() {
  if (id_ != 0) glDeleteVertexArrays(1, &id_);
}

VertexArray::VertexArray(VertexArray&& other) noexcept : id_(std::exchange(other.id_, 0)) {}

VertexArray& VertexArray::operator=(VertexArray&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteVertexArrays(1, &id_);
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}

void VertexArray::bind() const { glBindVertexArray(id_); }

void VertexArray::setFloatAttribute(GLuint location, const Buffer& buffer, int components, std::size_t strideBytes,
                                    std::size_t offsetBytes) {
  glBindVertexArray(id_);
  glBindBuffer(GL_ARRAY_BUFFER, buffer.id());
  glEnableVertexAttribArray(location);
  glVertexAttribPointer(location, components, GL_FLOAT, GL_FALSE, static_cast<GLsizei>(strideBytes),
                        reinterpret_cast<const void*>(offsetBytes));
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void VertexArray::setIndexBuffer(const Buffer& buffer) {
  glBindVertexArray(id_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffer.id());
  glBindVertexArray(0);
}

GLuint VertexArray::release() { return std::exchange(id_, 0); }

}  // namespace firn::gl
