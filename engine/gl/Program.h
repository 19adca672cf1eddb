#pragma once
// Move-only owner of a linked compute program.
#include <string>

#include "gl/GL.h"
#include "gl/ShaderLibrary.h"

namespace firn::gl {

class Program {
 public:
  Program() = default;
  // Compiles and links `path` from `library`. A compile or link failure throws GLError with the pass name,
  // file:line and the driver's log; a successful compile with a non-empty log prints it as a warning.
  static Program compute(const ShaderLibrary& library, const std::string& path, const ShaderOptions& options);

  ~Program();
  Program(Program&& other) noexcept;
  Program& operator=(Program&& other) noexcept;
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  GLuint id() const { return id_; }
  const std::string& name() const { return name_; }
  void use() const;

  // Sets a uint uniform; the program must be in use. A name the compiler optimised away is ignored.
  void set(const char* name, unsigned value) const;

  GLuint release();

 private:
  GLuint id_ = 0;
  std::string name_;
};

}  // namespace firn::gl
