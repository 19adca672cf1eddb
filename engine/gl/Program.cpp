#include "gl/Program.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "Error.h"

namespace firn::gl {

namespace {

// The info log of a shader (glGetShaderiv, glGetShaderInfoLog) or a program (glGetProgramiv, …).
template <typename GetParameter, typename GetLog>
std::string infoLog(GLuint object, GetParameter getParameter, GetLog getLog) {
  GLint length = 0;
  getParameter(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  getLog(object, length, nullptr, log.data());
  log.resize(std::char_traits<char>::length(log.c_str()));
  return log;
}

}  // namespace

Program Program::compute(const ShaderLibrary& library, const std::string& path, const ShaderOptions& options) {
  const PreprocessedShader source = library.preprocess(path, options);
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  const char* text = source.text.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint compiled = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
  const std::string compileLog = ShaderLibrary::translateLog(infoLog(shader, glGetShaderiv, glGetShaderInfoLog), source);
  if (!compiled) {
    glDeleteShader(shader);
    throw GLError("compiling " + path + " failed:\n" + compileLog);
  }
  if (!compileLog.empty() && compileLog.find_first_not_of(" \n") != std::string::npos) {
    std::fprintf(stderr, "firn: warning: compiling %s:\n%s\n", path.c_str(), compileLog.c_str());
  }

  Program program;
  program.name_ = path;
  program.id_ = glCreateProgram();
  glAttachShader(program.id_, shader);
  glLinkProgram(program.id_);
  glDetachShader(program.id_, shader);
  glDeleteShader(shader);
  GLint linked = GL_FALSE;
  glGetProgramiv(program.id_, GL_LINK_STATUS, &linked);
  if (!linked) throw GLError("linking " + path + " failed:\n" + ShaderLibrary::translateLog(infoLog(program.id_, glGetProgramiv, glGetProgramInfoLog), source));
  return program;
}

Program::~Program() {
  if (id_ != 0) glDeleteProgram(id_);
}

Program::Program(Program&& other) noexcept : id_(std::exchange(other.id_, 0)), name_(std::move(other.name_)) {}

Program& Program::operator=(Program&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteProgram(id_);
    id_ = std::exchange(other.id_, 0);
    name_ = std::move(other.name_);
  }
  return *this;
}

void Program::use() const { glUseProgram(id_); }

void Program::set(const char* name, unsigned value) const { glUniform1ui(glGetUniformLocation(id_, name), value); }

GLuint Program::release() { return std::exchange(id_, 0); }

}  // namespace firn::gl
