// gl::Buffer's storage: zero-filled at any size.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "GlTest.h"
#include "gl/Buffer.h"
#include "gl/GL.h"

namespace {

// A size that is not a multiple of 4 (the surface's buffers grow by a factor, to any size) is zeroed too: a clear
// of 32-bit words over 4 n + 1 bytes is GL_INVALID_VALUE, which left such a buffer as the driver gave it.
TEST(Buffer, AnySizeIsZeroFilledWithoutAGlError) {
  firn::test::glContext();
  while (glGetError() != GL_NO_ERROR) {
  }
  for (const std::size_t bytes : {std::size_t(13), std::size_t(4097), std::size_t(16)}) {
    const firn::gl::Buffer buffer(bytes);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << bytes << " bytes";
    EXPECT_EQ(buffer.bytes(), bytes);
    std::vector<std::uint8_t> contents(bytes, 0xFF);
    buffer.download(0, bytes, contents.data());
    EXPECT_EQ(contents, std::vector<std::uint8_t>(bytes, 0)) << bytes << " bytes";
  }
  const std::vector<std::uint8_t> data = {1, 2, 3, 4, 5};
  const firn::gl::Buffer uploaded(data.size(), data.data());
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  std::vector<std::uint8_t> contents(data.size());
  uploaded.download(0, data.size(), contents.data());
  EXPECT_EQ(contents, data);
}

}  // namespace
