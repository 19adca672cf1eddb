#include "render/Image.h"

#include <stdexcept>
#include <string>

#include "Error.h"
#include "gl/Framebuffer.h"
#include "io/AtomicFile.h"

// stb's implementation is C written for C compilers' warnings; it trips -Wextra and is not ours to change.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace firn::render {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) {
  throw InputError(path.string() + ": " + problem);
}

void appendBytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

}  // namespace

Image readFramebuffer(glm::ivec2 sizePx) { return {sizePx.x, sizePx.y, gl::readRgba8TopRowFirst(sizePx)}; }

void writePng(const std::filesystem::path& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != std::size_t(image.width) * std::size_t(image.height) * 4) {
    throw std::invalid_argument("writePng: " + std::to_string(image.rgba.size()) + " bytes do not make a " +
                                std::to_string(image.width) + "×" + std::to_string(image.height) + " RGBA image");
  }
  std::string png;
  if (!stbi_write_png_to_func(appendBytes, &png, image.width, image.height, 4, image.rgba.data(), image.width * 4)) {
    fail(path, "encoding the PNG failed");
  }
  writeFileAtomically(path, png, "PNG");
}

}  // namespace firn::render
