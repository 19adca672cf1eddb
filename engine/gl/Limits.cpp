#include "gl/Limits.h"

#include <regex>
#include <sstream>

#include "Error.h"
#include "gl/GL.h"
#include "gl/ShaderLibrary.h"

namespace firn::gl {

namespace {

// The limits a requirement may name. Each is one number for glGetInteger64v.
const std::map<std::string, GLenum>& queryableLimits() {
  static const std::map<std::string, GLenum> limits = {
      {"GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS", GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS},
      {"GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS},
      {"GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS", GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS},
      {"GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS", GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS},
      {"GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS", GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS},
      {"GL_MAX_COMPUTE_SHARED_MEMORY_SIZE", GL_MAX_COMPUTE_SHARED_MEMORY_SIZE},
      {"GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS", GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS},
      {"GL_MAX_UNIFORM_BUFFER_BINDINGS", GL_MAX_UNIFORM_BUFFER_BINDINGS},
      {"GL_MAX_SHADER_STORAGE_BLOCK_SIZE", GL_MAX_SHADER_STORAGE_BLOCK_SIZE},
  };
  return limits;
}

}  // namespace

std::vector<LimitRequirement> parseRequiredLimits(const std::string& contractText) {
  static const std::regex requirementLine(R"(^\s*#\s*define\s+(FIRN_REQUIRED_\w+)\b(.*)$)");
  static const std::regex valueAndLimit(R"(^\s+(\d+)\s*//\s*(GL_\w+).*$)");
  std::vector<LimitRequirement> requirements;
  std::istringstream lines(contractText);
  std::string line;
  while (std::getline(lines, line)) {
    std::smatch define;
    if (!std::regex_match(line, define, requirementLine)) continue;
    const std::string rest = define[2].str();
    std::smatch parts;
    if (!std::regex_match(rest, parts, valueAndLimit) || queryableLimits().count(parts[2].str()) == 0) {
      throw GLError("common/gpu_contract.h: " + define[1].str() +
                    " must be a number followed by a comment that begins with the GL limit it is held to (one of "
                    "engine/gl/Limits.cpp's), got \"" + line + "\"");
    }
    requirements.push_back({define[1].str(), parts[2].str(), std::stoll(parts[1].str())});
  }
  return requirements;
}

const std::vector<LimitRequirement>& requiredLimits() {
  static const std::vector<LimitRequirement> requirements =
      parseRequiredLimits(embeddedShaderFiles().at("common/gpu_contract.h"));
  return requirements;
}

DriverLimits queryLimits(const std::vector<LimitRequirement>& requirements) {
  DriverLimits found;
  for (const LimitRequirement& requirement : requirements) {
    GLint64 value = 0;
    glGetInteger64v(queryableLimits().at(requirement.glLimit), &value);
    found[requirement.glLimit] = value;
  }
  return found;
}

void checkLimits(const std::vector<LimitRequirement>& requirements, const DriverLimits& found,
                 const std::string& renderer) {
  std::string shortfalls;
  for (const LimitRequirement& requirement : requirements) {
    const auto value = found.find(requirement.glLimit);
    const long long foundValue = value == found.end() ? 0 : value->second;
    if (foundValue >= requirement.required) continue;
    shortfalls += "\n  " + requirement.glLimit + " = " + std::to_string(foundValue) + ", Firn needs at least " +
                  std::to_string(requirement.required) + " (" + requirement.name + ")";
  }
  if (!shortfalls.empty()) {
    throw NoOpenGLError("OpenGL from " + renderer + " offers less than Firn needs (docs/platform.md, Limits):" +
                        shortfalls);
  }
}

}  // namespace firn::gl
