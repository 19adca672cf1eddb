#include "gl/BufferBindings.h"

#include <stdexcept>
#include <string>

#include "gl/Program.h"

namespace firn::gl {

void BufferBindings::set(std::vector<const Buffer*>& points, GLuint binding, const Buffer& buffer) {
  if (points.size() <= binding) points.resize(binding + 1, nullptr);
  points[binding] = &buffer;
}

void BufferBindings::storage(GLuint binding, const Buffer& buffer) { set(storage_, binding, buffer); }

void BufferBindings::uniform(GLuint binding, const Buffer& buffer) { set(uniform_, binding, buffer); }

void BufferBindings::texture(GLuint unit, const BufferTexture& texture) {
  if (textures_.size() <= unit) textures_.resize(unit + 1, nullptr);
  textures_[unit] = &texture;
}

void BufferBindings::bindFor(const Program& program) const {
  for (std::size_t unit = 0; unit < textures_.size(); ++unit) {
    if (textures_[unit] != nullptr) textures_[unit]->bind(GLuint(unit));
  }
  for (const GLuint binding : program.storageBindings()) {
    if (binding >= storage_.size() || storage_[binding] == nullptr || !*storage_[binding]) {
      throw std::logic_error(program.name() + " declares storage binding " + std::to_string(binding) +
                             ", which no part of the GPU state provides");
    }
    storage_[binding]->bindStorage(binding);
  }
  for (const GLuint binding : program.uniformBindings()) {
    if (binding >= uniform_.size() || uniform_[binding] == nullptr || !*uniform_[binding]) {
      throw std::logic_error(program.name() + " declares uniform binding " + std::to_string(binding) +
                             ", which no part of the GPU state provides");
    }
    uniform_[binding]->bindUniform(binding);
  }
}

}  // namespace firn::gl
