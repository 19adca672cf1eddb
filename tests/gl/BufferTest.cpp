// gl::Buffer's storage: zero-filled at any size, and an upload right after the fill is kept.
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


// A buffer is zero-filled when made (glClearBufferData), and the block table's header is uploaded into it at once.
// NVIDIA's driver (580.159, H100) landed the clear after that glBufferSubData: the header's pool capacity read 0,
// no block was ever listed, and no particle moved (docs/platform.md, NVIDIA). Every byte uploaded must read back,
// for a header-sized upload and for a large one.
TEST(Buffer, UploadRightAfterTheZeroFillIsKept) {
  firn::test::glContext();
  for (const std::size_t bytes : {std::size_t(352 + 4096 * 16), std::size_t(1) << 22}) {
    firn::gl::Buffer buffer(bytes);
    std::vector<std::uint32_t> header(88);
    for (std::size_t i = 0; i < header.size(); ++i) header[i] = std::uint32_t(i * 2654435761u + 1u);
    buffer.upload(0, header.size() * sizeof(std::uint32_t), header.data());
    std::vector<std::uint32_t> contents(header.size());
    buffer.download(0, contents.size() * sizeof(std::uint32_t), contents.data());
    EXPECT_EQ(contents, header) << bytes << " bytes";
  }
}

}  // namespace
