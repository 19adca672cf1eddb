#pragma once
// Move-only owner of a linked program: a compute program, or a vertex + fragment program for drawing.
#include <string>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gl/GL.h"
#include "gl/ShaderLibrary.h"

namespace firn::gl {

// While one is alive, every shader stage Program compiles is also kept here, as glShaderSource received it: for
// holding each program Firn builds to another compiler and to the stated limits (tests/gl/PortabilityTest.cpp).
// A drawing program's vertex stage comes just before its fragment stage. One log at a time, on the thread that owns
// the context.
class ShaderSourceLog {
 public:
  struct Stage {
    GLenum type;  // GL_COMPUTE_SHADER, GL_VERTEX_SHADER, GL_FRAGMENT_SHADER
    std::string path;
    ShaderOptions options;
    PreprocessedShader source;  // source.text is the driver's input
  };

  ShaderSourceLog();  // throws GLError while another log is alive
  ~ShaderSourceLog();
  ShaderSourceLog(const ShaderSourceLog&) = delete;
  ShaderSourceLog& operator=(const ShaderSourceLog&) = delete;

  const std::vector<Stage>& stages() const { return stages_; }

 private:
  friend class Program;
  std::vector<Stage> stages_;
};

class Program {
 public:
  Program() = default;
  // Compiles and links `path` from `library`. A compile or link failure throws GLError with the pass name,
  // file:line and the driver's log; a successful compile with a non-empty log prints it as a warning.
  static Program compute(const ShaderLibrary& library, const std::string& path, const ShaderOptions& options);
  // Compiles `vertexPath` and `fragmentPath` with the same options and links them; failures as for compute().
  static Program graphics(const ShaderLibrary& library, const std::string& vertexPath, const std::string& fragmentPath,
                          const ShaderOptions& options);

  ~Program();
  Program(Program&& other) noexcept;
  Program& operator=(Program&& other) noexcept;
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  GLuint id() const { return id_; }
  const std::string& name() const { return name_; }
  // The binding points of the shader storage and uniform blocks the linked program declares (as the driver reports
  // them: blocks it found unused may be left out), and a compute program's work-group size.
  const std::vector<GLuint>& storageBindings() const { return storageBindings_; }
  // The binding point of the storage block named `block`, or -1 where the program has no such block in use.
  int storageBlockBinding(const std::string& block) const;
  // Each member of the storage blocks (GL_BUFFER_VARIABLE) by its name's first identifier ("slots" for
  // "slots[0].block"), with its block's binding point.
  std::vector<std::pair<std::string, GLuint>> storageMembers() const;
  const std::vector<GLuint>& uniformBindings() const { return uniformBindings_; }
  glm::ivec3 workGroupSize() const;
  void use() const;

  // Set a uniform; the program must be in use. A name the compiler optimised away is ignored.
  void set(const char* name, unsigned value) const;
  void set(const char* name, int value) const;  // also a sampler's texture unit
  void set(const char* name, float value) const;
  void set(const char* name, const glm::vec2& value) const;
  void set(const char* name, const glm::vec3& value) const;
  void set(const char* name, const glm::vec4& value) const;
  void set(const char* name, const glm::mat4& value) const;
  void set(const char* name, const std::vector<glm::vec4>& values) const;  // a vec4 array from element 0

  GLuint release();

 private:
  struct Stage;
  static Program link(const std::string& name, const std::vector<Stage>& stages);

  GLuint id_ = 0;
  std::string name_;
  std::vector<GLuint> storageBindings_;
  std::vector<GLuint> uniformBindings_;
};

}  // namespace firn::gl
