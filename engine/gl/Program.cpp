#include "gl/Program.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

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

// The binding points of a linked program's blocks of `interface` (GL_SHADER_STORAGE_BLOCK or GL_UNIFORM_BLOCK).
std::vector<GLuint> blockBindings(GLuint program, GLenum interface) {
  GLint blocks = 0;
  glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &blocks);
  std::vector<GLuint> bindings;
  for (GLint block = 0; block < blocks; ++block) {
    const GLenum property = GL_BUFFER_BINDING;
    GLint binding = 0;
    glGetProgramResourceiv(program, interface, GLuint(block), 1, &property, 1, nullptr, &binding);
    bindings.push_back(GLuint(binding));
  }
  return bindings;
}

ShaderSourceLog* activeLog = nullptr;

}  // namespace

ShaderSourceLog::ShaderSourceLog() {
  if (activeLog != nullptr) throw GLError("a ShaderSourceLog is already recording");
  activeLog = this;
}

ShaderSourceLog::~ShaderSourceLog() { activeLog = nullptr; }

// One compiled shader stage. It deletes its shader object when done: a linked program keeps what it needs.
struct Program::Stage {
  Stage(const ShaderLibrary& library, GLenum type, std::string stagePath, const ShaderOptions& options)
      : path(std::move(stagePath)), source(library.preprocess(path, options)) {
    if (activeLog != nullptr) activeLog->stages_.push_back({type, path, options, source});
    shader = glCreateShader(type);
    const char* text = source.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint compiled = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
    const std::string log = ShaderLibrary::translateLog(infoLog(shader, glGetShaderiv, glGetShaderInfoLog), source);
    if (!compiled) {
      glDeleteShader(shader);
      throw GLError("compiling " + path + " failed:\n" + log);
    }
    if (!log.empty() && log.find_first_not_of(" \n") != std::string::npos) {
      std::fprintf(stderr, "firn: warning: compiling %s:\n%s\n", path.c_str(), log.c_str());
    }
  }
  ~Stage() {
    if (shader != 0) glDeleteShader(shader);
  }
  Stage(Stage&& other) noexcept
      : shader(std::exchange(other.shader, 0)), path(std::move(other.path)), source(std::move(other.source)) {}
  Stage& operator=(Stage&&) = delete;
  Stage(const Stage&) = delete;
  Stage& operator=(const Stage&) = delete;

  GLuint shader = 0;
  std::string path;
  PreprocessedShader source;
};

Program Program::link(const std::string& name, const std::vector<Stage>& stages) {
  Program program;
  program.name_ = name;
  program.id_ = glCreateProgram();
  for (const Stage& stage : stages) glAttachShader(program.id_, stage.shader);
  glLinkProgram(program.id_);
  for (const Stage& stage : stages) glDetachShader(program.id_, stage.shader);
  GLint linked = GL_FALSE;
  glGetProgramiv(program.id_, GL_LINK_STATUS, &linked);
  if (!linked) {
    const std::string log = infoLog(program.id_, glGetProgramiv, glGetProgramInfoLog);
    // Line numbers in a link log can be mapped back only when a single source could have produced them.
    throw GLError("linking " + name + " failed:\n" +
                  (stages.size() == 1 ? ShaderLibrary::translateLog(log, stages.front().source) : log));
  }
  // Debuggers (RenderDoc, Nsight, apitrace) show the shader's path instead of a number.
  glObjectLabel(GL_PROGRAM, program.id_, GLsizei(name.size()), name.c_str());
  program.storageBindings_ = blockBindings(program.id_, GL_SHADER_STORAGE_BLOCK);
  program.uniformBindings_ = blockBindings(program.id_, GL_UNIFORM_BLOCK);
  return program;
}

int Program::storageBlockBinding(const std::string& block) const {
  const GLuint index = glGetProgramResourceIndex(id_, GL_SHADER_STORAGE_BLOCK, block.c_str());
  if (index == GL_INVALID_INDEX) return -1;
  const GLenum property = GL_BUFFER_BINDING;
  GLint binding = 0;
  glGetProgramResourceiv(id_, GL_SHADER_STORAGE_BLOCK, index, 1, &property, 1, nullptr, &binding);
  return binding;
}

std::vector<std::pair<std::string, GLuint>> Program::storageMembers() const {
  GLint variables = 0, longestName = 0;
  glGetProgramInterfaceiv(id_, GL_BUFFER_VARIABLE, GL_ACTIVE_RESOURCES, &variables);
  glGetProgramInterfaceiv(id_, GL_BUFFER_VARIABLE, GL_MAX_NAME_LENGTH, &longestName);
  std::vector<std::pair<std::string, GLuint>> members;
  for (GLint variable = 0; variable < variables; ++variable) {
    std::string name(std::size_t(std::max(longestName, 1)), '\0');
    glGetProgramResourceName(id_, GL_BUFFER_VARIABLE, GLuint(variable), longestName, nullptr, name.data());
    name.resize(std::strlen(name.c_str()));
    name = name.substr(0, name.find_first_of("[."));  // "slots[0].block": slots
    const GLenum blockIndex = GL_BLOCK_INDEX, bufferBinding = GL_BUFFER_BINDING;
    GLint block = -1, binding = 0;
    glGetProgramResourceiv(id_, GL_BUFFER_VARIABLE, GLuint(variable), 1, &blockIndex, 1, nullptr, &block);
    if (block < 0) continue;
    glGetProgramResourceiv(id_, GL_SHADER_STORAGE_BLOCK, GLuint(block), 1, &bufferBinding, 1, nullptr, &binding);
    members.emplace_back(name, GLuint(binding));
  }
  return members;
}

Program Program::compute(const ShaderLibrary& library, const std::string& path, const ShaderOptions& options) {
  std::vector<Stage> stages;
  stages.emplace_back(library, GL_COMPUTE_SHADER, path, options);
  return link(path, stages);
}

Program Program::graphics(const ShaderLibrary& library, const std::string& vertexPath, const std::string& fragmentPath,
                          const ShaderOptions& options) {
  std::vector<Stage> stages;
  stages.reserve(2);
  stages.emplace_back(library, GL_VERTEX_SHADER, vertexPath, options);
  stages.emplace_back(library, GL_FRAGMENT_SHADER, fragmentPath, options);
  return link(vertexPath + " + " + fragmentPath, stages);
}

Program::~Program() {
  if (id_ != 0) glDeleteProgram(id_);
}

Program::Program(Program&& other) noexcept
    : id_(std::exchange(other.id_, 0)),
      name_(std::move(other.name_)),
      storageBindings_(std::move(other.storageBindings_)),
      uniformBindings_(std::move(other.uniformBindings_)) {}

Program& Program::operator=(Program&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteProgram(id_);
    id_ = std::exchange(other.id_, 0);
    name_ = std::move(other.name_);
    storageBindings_ = std::move(other.storageBindings_);
    uniformBindings_ = std::move(other.uniformBindings_);
  }
  return *this;
}

void Program::use() const { glUseProgram(id_); }

glm::ivec3 Program::workGroupSize() const {
  glm::ivec3 size(0);
  glGetProgramiv(id_, GL_COMPUTE_WORK_GROUP_SIZE, &size.x);
  return size;
}

void Program::set(const char* name, unsigned value) const { glUniform1ui(glGetUniformLocation(id_, name), value); }

void Program::set(const char* name, int value) const { glUniform1i(glGetUniformLocation(id_, name), value); }

void Program::set(const char* name, float value) const { glUniform1f(glGetUniformLocation(id_, name), value); }

void Program::set(const char* name, const glm::vec2& value) const {
  glUniform2fv(glGetUniformLocation(id_, name), 1, glm::value_ptr(value));
}

void Program::set(const char* name, const glm::vec3& value) const {
  glUniform3fv(glGetUniformLocation(id_, name), 1, glm::value_ptr(value));
}

void Program::set(const char* name, const glm::vec4& value) const {
  glUniform4fv(glGetUniformLocation(id_, name), 1, glm::value_ptr(value));
}

void Program::set(const char* name, const glm::mat4& value) const {
  glUniformMatrix4fv(glGetUniformLocation(id_, name), 1, GL_FALSE, glm::value_ptr(value));
}

void Program::set(const char* name, const std::vector<glm::vec4>& values) const {
  glUniform4fv(glGetUniformLocation(id_, name), static_cast<GLsizei>(values.size()),
               reinterpret_cast<const GLfloat*>(values.data()));
}

GLuint Program::release() { return std::exchange(id_, 0); }

}  // namespace firn::gl
