#pragma once
// Firn's failures carry the process exit status of the command-line contract (docs/command-line.md, Exit status):
// 2 bad input, 3 the simulation became unstable or overflowed, 4 no usable OpenGL 4.3.
#include <stdexcept>
#include <string>

namespace firn {

enum class ExitCode : int { Success = 0, BadInput = 2, Unstable = 3, NoOpenGL = 4 };

class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

// A scene, command line or file the user gave is wrong; the message names the file, the key and the problem.
class InputError : public Error {
 public:
  explicit InputError(const std::string& message) : Error(ExitCode::BadInput, message) {}
};

// The simulation overflowed its fixed-point range or produced a non-finite value; the message says when,
// where and what to change.
class SimulationError : public Error {
 public:
  explicit SimulationError(const std::string& message) : Error(ExitCode::Unstable, message) {}
};

// In a run over several processes (docs/distributed.md): another process stopped the run, and says why itself.
class StoppedElsewhere : public Error {
 public:
  explicit StoppedElsewhere(const std::string& message) : Error(ExitCode::Unstable, message) {}
};

// No OpenGL 4.3 core context could be had, or a required entry point is missing; the message says what was found.
class NoOpenGLError : public Error {
 public:
  explicit NoOpenGLError(const std::string& message) : Error(ExitCode::NoOpenGL, message) {}
};

// A GL program failed to compile or link, or the driver reported an error: a defect, not bad input.
class GLError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace firn
