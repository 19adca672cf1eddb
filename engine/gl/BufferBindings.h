#pragma once
// The buffers a program may read, by binding point: each part of a GPU state publishes its buffers at the points of
// its binding range, and a program binds, before it runs, exactly the blocks its shaders declare (Program's
// storageBindings and uniformBindings, read from the linked program). So no pass relies on an earlier call having
// left a buffer bound, and a block that no part provides is an error naming the program and the binding.
#include <cstddef>
#include <vector>

#include "gl/Buffer.h"
#include "gl/BufferTexture.h"
#include "gl/GL.h"

namespace firn::gl {

class Program;

class BufferBindings {
 public:
  void storage(GLuint binding, const Buffer& buffer);
  void uniform(GLuint binding, const Buffer& buffer);
  // A buffer texture every program finds at `unit` (bound for each, whether it samples it or not: they are few).
  void texture(GLuint unit, const BufferTexture& texture);

  // Binds every block `program` declares; throws std::logic_error if one has no buffer here.
  void bindFor(const Program& program) const;

 private:
  static void set(std::vector<const Buffer*>& points, GLuint binding, const Buffer& buffer);

  std::vector<const Buffer*> storage_;  // by storage binding point, null where nothing is published
  std::vector<const Buffer*> uniform_;  // by uniform binding point
  std::vector<const BufferTexture*> textures_;  // by texture unit, null where nothing is published
};

}  // namespace firn::gl
