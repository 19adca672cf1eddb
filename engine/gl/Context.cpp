#include "gl/Context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "Error.h"
#include "gl/Debug.h"
#include "gl/GL.h"
#include "gl/Limits.h"

namespace firn::gl {

struct HeadlessContext::Egl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

namespace {

bool extensionListed(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t length = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += length) {
    const bool startsWord = p == list || p[-1] == ' ';
    const bool endsWord = p[length] == ' ' || p[length] == '\0';
    if (startsWord && endsWord) return true;
  }
  return false;
}

template <typename Function>
Function eglFunction(const char* name) {
  return reinterpret_cast<Function>(eglGetProcAddress(name));
}

struct DisplayChoice {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;
};

// Returns the display of EGL device `index`, or when index < 0 of hardware device `gpuOrdinal` modulo their number.
DisplayChoice deviceDisplay(int requestedIndex, int gpuOrdinal) {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!extensionListed(clientExtensions, "EGL_EXT_platform_device")) return {};
  auto queryDevices = eglFunction<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
  auto queryDeviceString = eglFunction<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
  auto getPlatformDisplay = eglFunction<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
  if (!queryDevices || !getPlatformDisplay) return {};
  EGLint count = 0;
  if (!queryDevices(0, nullptr, &count) || count == 0) return {};
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
  queryDevices(count, devices.data(), &count);
  if (requestedIndex >= count) {
    throw NoOpenGLError("FIRN_EGL_DEVICE=" + std::to_string(requestedIndex) + " but EGL lists only " +
                        std::to_string(count) + " device(s)");
  }
  std::vector<int> candidates;
  for (int i = 0; i < count; ++i) {
    if (requestedIndex >= 0 && i != requestedIndex) continue;
    const char* deviceExtensions =
        queryDeviceString ? queryDeviceString(devices[static_cast<std::size_t>(i)], EGL_EXTENSIONS) : nullptr;
    // Mesa lists its software rasterizer as a device too; prefer real hardware unless asked for it.
    if (requestedIndex < 0 && extensionListed(deviceExtensions, "EGL_MESA_device_software")) continue;
    candidates.push_back(i);
  }
  // From the ordinal's device on, the first that gives a display.
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const int i = candidates[(std::size_t(std::max(gpuOrdinal, 0)) + k) % candidates.size()];
    EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<std::size_t>(i)], nullptr);
    if (display != EGL_NO_DISPLAY) return {display, "EGL device " + std::to_string(i)};
  }
  return {};
}

DisplayChoice surfacelessDisplay() {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!extensionListed(clientExtensions, "EGL_MESA_platform_surfaceless")) return {};
  auto getPlatformDisplay = eglFunction<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
  if (!getPlatformDisplay) return {};
  EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  return {display, "Mesa surfaceless"};
}

int requestedDeviceIndex() {
  const char* value = std::getenv("FIRN_EGL_DEVICE");
  if (value == nullptr || *value == '\0') return -1;
  char* end = nullptr;
  const long index = std::strtol(value, &end, 10);
  if (*end != '\0' || index < 0) {
    throw NoOpenGLError(std::string("FIRN_EGL_DEVICE must be a device index (0, 1, …), got \"") + value + "\"");
  }
  return static_cast<int>(index);
}

std::string eglErrorText() {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "EGL error 0x%04X", static_cast<unsigned>(eglGetError()));
  return buffer;
}

}  // namespace

bool hasExtension(const char* name) {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    const auto* extension = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
    if (extension != nullptr && std::strcmp(extension, name) == 0) return true;
  }
  return false;
}

HeadlessContext::HeadlessContext(int gpuOrdinal) : egl_(std::make_unique<Egl>()) {
  const int deviceIndex = requestedDeviceIndex();
  DisplayChoice choice = deviceDisplay(deviceIndex, gpuOrdinal);
  if (choice.display == EGL_NO_DISPLAY && deviceIndex < 0) choice = surfacelessDisplay();
  if (choice.display == EGL_NO_DISPLAY && deviceIndex < 0) {
    choice = {eglGetDisplay(EGL_DEFAULT_DISPLAY), "EGL default display"};
  }
  if (choice.display == EGL_NO_DISPLAY) {
    throw NoOpenGLError("no EGL display: neither EGL_EXT_platform_device nor EGL_MESA_platform_surfaceless "
                        "gave one (install libegl-mesa0 for Mesa's llvmpipe)");
  }
  egl_->display = choice.display;
  info_.platform = choice.platform;

  EGLint major = 0, minor = 0;
  if (!eglInitialize(egl_->display, &major, &minor)) {
    throw NoOpenGLError("eglInitialize failed on " + choice.platform + " (" + eglErrorText() + ")");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    throw NoOpenGLError("EGL on " + choice.platform + " does not offer desktop OpenGL (" + eglErrorText() + ")");
  }
  const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configCount = 0;
  const bool haveConfig = eglChooseConfig(egl_->display, configAttributes, &config, 1, &configCount) && configCount > 0;
  const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      4,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
#ifndef NDEBUG
                                      EGL_CONTEXT_OPENGL_DEBUG,
                                      EGL_TRUE,
#endif
                                      EGL_NONE};
  // A config-less context needs EGL_KHR_no_config_context; pass the chosen config where there is one.
  egl_->context = eglCreateContext(egl_->display, haveConfig ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT,
                                   contextAttributes);
  if (egl_->context == EGL_NO_CONTEXT) {
    const char* vendor = eglQueryString(egl_->display, EGL_VENDOR);
    throw NoOpenGLError("cannot create an OpenGL 4.3 core context on " + choice.platform + " (EGL " +
                        std::to_string(major) + "." + std::to_string(minor) + ", vendor " +
                        (vendor ? vendor : "unknown") + ", " + eglErrorText() + "); Firn needs OpenGL 4.3 compute shaders");
  }
  if (!eglMakeCurrent(egl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_->context)) {
    throw NoOpenGLError("cannot make the OpenGL context current without a surface on " + choice.platform + " (" +
                        eglErrorText() + ")");
  }
  loadGLFunctions(info_);
  enableDebugOutput();
}

HeadlessContext::~HeadlessContext() {
  if (egl_->display == EGL_NO_DISPLAY) return;
  eglMakeCurrent(egl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (egl_->context != EGL_NO_CONTEXT) eglDestroyContext(egl_->display, egl_->context);
  eglTerminate(egl_->display);
}

void loadGLFunctions(ContextInfo& info) {
  glewExperimental = GL_TRUE;
  const GLenum status = glewInit();
  // Debian's GLEW is built for GLX: on an EGL context it reports GLEW_ERROR_NO_GLX_DISPLAY after it has
  // loaded every entry point, so that one code is accepted once the functions Firn calls are checked.
  if (status != GLEW_OK && status != GLEW_ERROR_NO_GLX_DISPLAY) {
    throw NoOpenGLError(std::string("GLEW could not load OpenGL: ") +
                        reinterpret_cast<const char*>(glewGetErrorString(status)));
  }
  const struct {
    const char* name;
    const void* entry;
  } required[] = {
      {"glDispatchCompute", reinterpret_cast<const void*>(glDispatchCompute)},
      {"glDispatchComputeIndirect", reinterpret_cast<const void*>(glDispatchComputeIndirect)},
      {"glMemoryBarrier", reinterpret_cast<const void*>(glMemoryBarrier)},
      {"glBindBufferBase", reinterpret_cast<const void*>(glBindBufferBase)},
      {"glBufferData", reinterpret_cast<const void*>(glBufferData)},
      {"glBufferSubData", reinterpret_cast<const void*>(glBufferSubData)},
      {"glGetBufferSubData", reinterpret_cast<const void*>(glGetBufferSubData)},
      {"glClearBufferData", reinterpret_cast<const void*>(glClearBufferData)},
      {"glCopyBufferSubData", reinterpret_cast<const void*>(glCopyBufferSubData)},
      {"glCreateShader", reinterpret_cast<const void*>(glCreateShader)},
      {"glCreateProgram", reinterpret_cast<const void*>(glCreateProgram)},
      {"glGetStringi", reinterpret_cast<const void*>(glGetStringi)},
      {"glGenQueries", reinterpret_cast<const void*>(glGenQueries)},
      {"glGetQueryObjectui64v", reinterpret_cast<const void*>(glGetQueryObjectui64v)},
      {"glUniform1i", reinterpret_cast<const void*>(glUniform1i)},
  };
  for (const auto& function : required) {
    if (function.entry == nullptr) {
      const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
      throw NoOpenGLError(std::string("OpenGL entry point ") + function.name + " is missing (GL_VERSION \"" +
                          (version ? version : "unknown") + "\"); Firn needs OpenGL 4.3 core");
    }
  }
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  info.vendor = reinterpret_cast<const char*>(glGetString(GL_VENDOR));
  info.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  info.version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  if (major < 4 || (major == 4 && minor < 3)) {
    throw NoOpenGLError("OpenGL " + info.version + " from " + info.renderer +
                        " is older than 4.3; Firn needs 4.3 compute shaders");
  }
  // Before any program is built: a driver short of a limit Firn relies on is refused here, by name, instead of
  // failing later in a compile or link log.
  checkLimits(requiredLimits(), queryLimits(requiredLimits()), info.renderer + " (" + info.version + ")");
  info.hasFloatAtomics = hasExtension("GL_NV_shader_atomic_float");
  GLint64 maxBlockBytes = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlockBytes);
  info.maxStorageBlockBytes = maxBlockBytes;
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  info.maxTextureBufferTexels = maxTexels;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &info.maxComputeWorkGroupCountX);
  // Both report KiB: NVX the dedicated memory free now, ATI the free memory for buffers (the first of four).
  constexpr GLenum currentAvailableVidmemNvx = 0x9049;  // GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX
  constexpr GLenum vboFreeMemoryAti = 0x87FB;           // GL_VBO_FREE_MEMORY_ATI
  GLint freeKiB[4] = {0, 0, 0, 0};
  if (hasExtension("GL_NVX_gpu_memory_info")) {
    glGetIntegerv(currentAvailableVidmemNvx, freeKiB);
  } else if (hasExtension("GL_ATI_meminfo")) {
    glGetIntegerv(vboFreeMemoryAti, freeKiB);
  }
  info.availableMemoryBytes = 1024LL * freeKiB[0];
  for (const char* software : {"llvmpipe", "softpipe", "swrast"}) {
    if (info.renderer.find(software) != std::string::npos) info.buffersInHostMemory = true;
  }
}

}  // namespace firn::gl
