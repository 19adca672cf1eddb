#pragma once
// What Firn requires of a driver beyond OpenGL 4.3's minimums, and the check that holds a context to it before any
// program is built. The requirements are the FIRN_REQUIRED_* defines of the contract the shaders share
// (common/gpu_contract.h, compiled into the binary), read as plain numbers: each define's comment begins with the
// GL limit it is held to, so this layer knows GL's names and nothing of the physics behind the numbers.
#include <map>
#include <string>
#include <vector>

namespace firn::gl {

struct LimitRequirement {
  std::string name;     // the define: "FIRN_REQUIRED_COMPUTE_STORAGE_BLOCKS"
  std::string glLimit;  // what the driver is asked: "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS"
  long long required = 0;
};

// The GL limits Firn can query, by name, as glGetInteger64v answers them.
using DriverLimits = std::map<std::string, long long>;

// Each "#define FIRN_REQUIRED_<NAME> <value>  // <GL limit> …" line of `contractText`. Throws GLError for a
// FIRN_REQUIRED_ define without a value or whose comment does not begin with a limit queryLimits knows.
std::vector<LimitRequirement> parseRequiredLimits(const std::string& contractText);

// The requirements of the contract compiled into the binary.
const std::vector<LimitRequirement>& requiredLimits();

// The current context's value of each required limit.
DriverLimits queryLimits(const std::vector<LimitRequirement>& requirements);

// Throws NoOpenGLError (exit 4) naming every limit `found` holds below its requirement, with the value found and
// the value needed; `renderer` names the driver in the message.
void checkLimits(const std::vector<LimitRequirement>& requirements, const DriverLimits& found,
                 const std::string& renderer);

}  // namespace firn::gl
