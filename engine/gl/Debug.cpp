#include "gl/Debug.h"

#include <cstdio>
#include <string>

#include "Error.h"
#include "gl/GL.h"

namespace firn::gl {

#ifndef NDEBUG
namespace {
bool debugErrorSeen = false;

void GLAPIENTRY printDebugMessage(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message,
                                  const void*) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  if (type == GL_DEBUG_TYPE_ERROR) debugErrorSeen = true;
  std::fprintf(stderr, "firn: GL debug: %s\n", message);
}
}  // namespace

void enableDebugOutput() {
  if (glDebugMessageCallback == nullptr) return;
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(printDebugMessage, nullptr);
}

void checkPass(const char* passName) {
  glFinish();
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR || debugErrorSeen) {
    debugErrorSeen = false;
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", error);
    throw GLError(std::string("GL error ") + code + " in pass " + passName);
  }
}
#else
void enableDebugOutput() {}
void checkPass(const char*) {}
#endif

}  // namespace firn::gl
