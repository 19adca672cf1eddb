#pragma once
// A headless OpenGL 4.3 core context through EGL: no window, no display server.
//
// Device choice: with EGL_EXT_platform_device the context is made on a GPU (FIRN_EGL_DEVICE=N picks the
// N-th EGL device, as listed by `firn --gl-info`); otherwise on Mesa's surfaceless platform (llvmpipe).
#include <memory>
#include <string>

namespace firn::gl {

struct ContextInfo {
  std::string platform;  // "EGL device 0", "Mesa surfaceless", …
  std::string vendor;
  std::string renderer;
  std::string version;
  bool hasFloatAtomics = false;  // GL_NV_shader_atomic_float
  long long maxStorageBlockBytes = 0;
  long long maxTextureBufferTexels = 0;  // GL_MAX_TEXTURE_BUFFER_SIZE: the collider fields' buffer texture
  int maxComputeWorkGroupCountX = 0;
  // GPU memory free when the context was made, where the driver says (GL_NVX_gpu_memory_info, GL_ATI_meminfo);
  // 0 where it does not.
  long long availableMemoryBytes = 0;
  // A software renderer (Mesa's llvmpipe, softpipe): its buffers live in host memory.
  bool buffersInHostMemory = false;
};

class HeadlessContext {
 public:
  // Throws NoOpenGLError (exit 4) with what was found when no GL 4.3 core context can be made. Without
  // FIRN_EGL_DEVICE the context is made on the GPU `gpuOrdinal` (modulo their number) of those EGL lists: a rank of a
  // run over MPI takes its place among the ranks on its machine.
  explicit HeadlessContext(int gpuOrdinal = 0);
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;

  const ContextInfo& info() const { return info_; }

 private:
  struct Egl;
  std::unique_ptr<Egl> egl_;
  ContextInfo info_;
};

// After a context is current: loads entry points with GLEW (accepting Debian GLEW's GLEW_ERROR_NO_GLX_DISPLAY
// on EGL only when every entry point Firn uses is present), checks the driver's limits against what Firn requires
// (gl/Limits.h), then fills ContextInfo's GL fields.
// Throws NoOpenGLError if the context is older than 4.3, an entry point is missing or a limit falls short.
void loadGLFunctions(ContextInfo& info);

bool hasExtension(const char* name);

}  // namespace firn::gl
