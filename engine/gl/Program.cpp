#include "gl/Program.h"

#include <cstdio>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

#include "Error.h"

namespace firn::gl {

namespace {

std::string shaderLog(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  log.resize(std::char_traits<char>::length(log.c_str()));
  return log;
}

std::string programLog(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, length, nullptr, log.data());
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
  const std::string compileLog = ShaderLibrary::translateLog(shaderLog(shader), source);
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
  if (!linked) throw GLError("linking " + path + " failed:\n" + ShaderLibrary::translateLog(programLog(program.id_), source));
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

void Program::set(const char* name, int value) const { glUniform1i(glGetUniformLocation(id_, name), value); }

void Program::set(const char* name, unsigned value) const { glUniform1ui(glGetUniformLocation(id_, name), value); }

void Program::set(const char* name, float value) const { glUniform1f(glGetUniformLocation(id_, name), value); }

void Program::set(const char* name, const glm::vec3& value) const {
  glUniform3fv(glGetUniformLocation(id_, name), 1, glm::value_ptr(value));
}

void Program::set(const char* name, const glm::ivec3& value) const {
  glUniform3iv(glGetUniformLocation(id_, name), 1, glm::value_ptr(value));
}

GLuint Program::release() { return std::exchange(id_, 0); }

}  // namespace firn::gl
