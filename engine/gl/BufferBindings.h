#pragma once
// The buffers a program may read, by binding point: each part of a GPU state publishes its buffers at the points of
// its binding range, and a program binds, before it runs, exactly the blocks its shaders declare (Program's
// storageBindings and uniformBindings, read from the linked program). So no pass relies on an earlier call having
// left a buffer bound, and a block that no part provides is an error naming the program and the binding.
#include <cstddef>
#include <string>
#include <vector>

#include "gl/Buffer.h"
#include "gl/BufferTexture.h"
#include "gl/GL.h"
#include "gl/StorageAccess.h"

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

  // The barriers between the passes that bind from here, from what each declares (gl/StorageAccess.h), called by
  // each pass around its dispatch. Before a pass that reads a buffer written since the last storage barrier, or
  // writes one read or written since, a storage barrier (GL_SHADER_STORAGE_BARRIER_BIT); before an indirect dispatch
  // whose `commands` were written since the last command barrier, a command barrier (GL_COMMAND_BARRIER_BIT). A pass
  // that declares nothing counts as reading and writing every block its program has.
  void beforePass(const StorageAccess& access, const Buffer* commands) const;
  void afterPass(const StorageAccess& access, const std::string& phase) const;
  // One barrier for every write still pending: for what reads without binding from here (the host, the renderer,
  // another pipeline's passes), at the end of a step's work.
  void completeWrites() const;
  // (GL_BUFFER_UPDATE_BARRIER_BIT too: host uploads and copies after the passes' writes.)

  // A pass's record: its phase name and what it read and wrote.
  struct PassRecord {
    std::string phase;
    StorageAccess access;
  };
  // Records every pass that runs from here on into `record` (null: stop recording): how benchmarks count the bytes
  // each pass moves. The record must outlive the recording.
  void recordPasses(std::vector<PassRecord>* record) const { record_ = record; }
  // Nothing published any more (for publishing anew, as when buffers are reallocated): the pending writes completed
  // first, the recording and the count of barriers kept.
  void unpublishAll();
  // The storage buffer at `binding`, or null where none is published.
  const Buffer* storageAt(GLuint binding) const;
  // The barriers placed so far (each glMemoryBarrier call once).
  std::size_t barriers() const { return barriers_; }

 private:
  void barrier(GLbitfield bits) const;

  static void set(std::vector<const Buffer*>& points, GLuint binding, const Buffer& buffer);

  std::vector<const Buffer*> storage_;  // by storage binding point, null where nothing is published
  std::vector<const Buffer*> uniform_;  // by uniform binding point
  std::vector<const BufferTexture*> textures_;  // by texture unit, null where nothing is published
  // The barriers' state: what passes read and wrote since the last storage barrier, and wrote since the last command
  // barrier. GL state of the command stream, which a const pass's run changes.
  mutable BindingSet readSinceBarrier_ = 0;
  mutable BindingSet writtenSinceBarrier_ = 0;
  mutable BindingSet writtenSinceCommandBarrier_ = 0;
  mutable std::vector<PassRecord>* record_ = nullptr;
  mutable std::size_t barriers_ = 0;
};

}  // namespace firn::gl
