#pragma once
// A rendered picture in memory, and PNG output.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/vec2.hpp>

namespace firn::render {

// 8-bit RGBA pixels, tightly packed, top row first.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;
};

// The picture in the framebuffer bound for reading, (0, 0)–sizePx: after glBindFramebuffer(GL_FRAMEBUFFER, 0),
// a window's back buffer (a screenshot). Needs a current GL context; waits for drawing to finish.
Image readFramebuffer(glm::ivec2 sizePx);

// Writes `image` as a PNG, through a temporary file renamed into place, so that a reader never sees half a
// file. Throws InputError naming the file if it cannot be written, std::invalid_argument if the pixel count
// does not match the size.
void writePng(const std::filesystem::path& path, const Image& image);

}  // namespace firn::render
