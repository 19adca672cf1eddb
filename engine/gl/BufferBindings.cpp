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

const Buffer* BufferBindings::storageAt(GLuint binding) const {
  return binding < storage_.size() ? storage_[binding] : nullptr;
}

void BufferBindings::barrier(GLbitfield bits) const {
  glMemoryBarrier(bits);
  ++barriers_;
  if (bits & GL_SHADER_STORAGE_BARRIER_BIT) readSinceBarrier_ = writtenSinceBarrier_ = 0;
  if (bits & GL_COMMAND_BARRIER_BIT) writtenSinceCommandBarrier_ = 0;
}

void BufferBindings::beforePass(const StorageAccess& access, const Buffer* commands) const {
  GLbitfield bits = 0;
  if ((access.reads & writtenSinceBarrier_) || (access.writes & (writtenSinceBarrier_ | readSinceBarrier_))) {
    bits |= GL_SHADER_STORAGE_BARRIER_BIT;
  }
  if (commands != nullptr) {
    // The commands' bindings, where they are published here; else any pending write may be theirs.
    BindingSet commandBits = 0;
    for (std::size_t binding = 0; binding < storage_.size(); ++binding) {
      if (storage_[binding] == commands) commandBits |= bindingBit(unsigned(binding));
    }
    if (writtenSinceCommandBarrier_ & (commandBits != 0 ? commandBits : ~BindingSet(0))) bits |= GL_COMMAND_BARRIER_BIT;
  }
  if (bits != 0) barrier(bits);
}

void BufferBindings::afterPass(const StorageAccess& access, const std::string& phase) const {
  if (record_ != nullptr) record_->push_back({phase, access});
  readSinceBarrier_ |= access.reads;
  writtenSinceBarrier_ |= access.writes;
  writtenSinceCommandBarrier_ |= access.writes;
}

void BufferBindings::completeWrites() const {
  if (writtenSinceBarrier_ == 0 && writtenSinceCommandBarrier_ == 0) return;
  barrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
          (writtenSinceCommandBarrier_ != 0 ? GL_COMMAND_BARRIER_BIT : 0));
}

void BufferBindings::unpublishAll() {
  completeWrites();
  storage_.clear();
  uniform_.clear();
  textures_.clear();
}

}  // namespace firn::gl
