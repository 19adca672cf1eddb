#include "voxelizer/ChildProcess.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <string>
#include <system_error>

#include "voxelizer/ProcessMemory.h"

namespace firn::voxelizer {
namespace {

// The child's exit statuses besides 0: `work` threw, or an allocation failed under the memory limit.
constexpr int kWorkThrew = 101;
constexpr int kOutOfMemory = 102;
// Of what the child writes to stderr, the tail is kept: the last line is what an assertion or abort says.
constexpr std::size_t kKeptStderrBytes = 4096;

using Clock = std::chrono::steady_clock;

std::string mebibytes(std::uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

std::string seconds(double valueS) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g s", valueS);
  return text;
}

// Only async-signal-safe calls from here on in the child: write, _exit.
void writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t written = write(fd, data, size);
    if (written < 0) {
      if (errno == EINTR) continue;
      return;
    }
    data += written;
    size -= std::size_t(written);
  }
}

void say(const char* text) { writeAll(STDERR_FILENO, text, std::strlen(text)); }

[[noreturn]] void runChild(const std::function<std::string()>& work, const ChildLimits& limits, int resultFd,
                           int stderrFd) {
  dup2(stderrFd, STDERR_FILENO);
  dup2(stderrFd, STDOUT_FILENO);  // nothing the work prints reaches the caller's stdout
  const rlim_t addressSpace = rlim_t(mappedBytes() + limits.memoryBytes);
  const rlimit memory{addressSpace, addressSpace};
  const auto cpuS = rlim_t(std::ceil(std::max(limits.cpuS, 1.0)));
  const rlimit cpu{cpuS, cpuS + 1};  // SIGXCPU at the soft limit, SIGKILL a second later
  const rlimit noCore{0, 0};         // an abort must not dump gigabytes of core
  setrlimit(RLIMIT_CORE, &noCore);
  setrlimit(RLIMIT_CPU, &cpu);
  setrlimit(RLIMIT_AS, &memory);
  std::set_new_handler([] {
    say("out of memory\n");
    _exit(kOutOfMemory);
  });
  try {
    const std::string result = work();
    writeAll(resultFd, result.data(), result.size());
  } catch (const std::exception& error) {
    say(error.what());
    say("\n");
    _exit(kWorkThrew);
  } catch (...) {
    _exit(kWorkThrew);
  }
  _exit(0);
}

std::string lastLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  const std::size_t newline = text.find_last_of('\n');
  return newline == std::string::npos ? text : text.substr(newline + 1);
}

std::string describeSignal(int signal) {
  const char* name = strsignal(signal);
  return "signal " + std::to_string(signal) + (name != nullptr ? std::string(" (") + name + ")" : std::string());
}

}  // namespace

ChildOutcome runInChildProcess(const std::function<std::string()>& work, const ChildLimits& limits) {
  int resultPipe[2], stderrPipe[2];
  if (pipe2(resultPipe, O_CLOEXEC) != 0) throw std::system_error(errno, std::generic_category(), "pipe");
  if (pipe2(stderrPipe, O_CLOEXEC) != 0) {
    const int error = errno;
    close(resultPipe[0]);
    close(resultPipe[1]);
    throw std::system_error(error, std::generic_category(), "pipe");
  }
  // What the parent buffered would otherwise be written twice, once by each process.
  std::fflush(nullptr);
  const pid_t child = fork();
  if (child < 0) {
    const int error = errno;
    for (int fd : {resultPipe[0], resultPipe[1], stderrPipe[0], stderrPipe[1]}) close(fd);
    throw std::system_error(error, std::generic_category(), "fork");
  }
  if (child == 0) {
    close(resultPipe[0]);
    close(stderrPipe[0]);
    runChild(work, limits, resultPipe[1], stderrPipe[1]);
  }
  close(resultPipe[1]);
  close(stderrPipe[1]);

  ChildOutcome outcome;
  std::string childStderr;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limits.wallS));
  pollfd fds[2] = {{resultPipe[0], POLLIN, 0}, {stderrPipe[0], POLLIN, 0}};
  int open = 2;
  bool timedOut = false;
  char buffer[1 << 16];
  while (open > 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) {
      timedOut = true;
      break;
    }
    const int ready = poll(fds, 2, int(std::min<long long>(left, std::numeric_limits<int>::max())));
    if (ready < 0 && errno != EINTR) break;
    for (int i = 0; i < 2 && ready > 0; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      const ssize_t got = read(fds[i].fd, buffer, sizeof buffer);
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) {
        close(fds[i].fd);
        fds[i].fd = -1;  // poll skips negative descriptors
        --open;
        continue;
      }
      std::string& into = i == 0 ? outcome.result : childStderr;
      into.append(buffer, std::size_t(got));
      if (i == 1 && childStderr.size() > kKeptStderrBytes) childStderr.erase(0, childStderr.size() - kKeptStderrBytes);
    }
  }
  for (const pollfd& fd : fds) {
    if (fd.fd >= 0) close(fd.fd);
  }
  // The pipes close when the child exits; a child that closed them and went on is still held to the deadline.
  int status = 0;
  while (!timedOut) {
    const pid_t waited = waitpid(child, &status, WNOHANG);
    if (waited == child || (waited < 0 && errno != EINTR)) break;
    if (Clock::now() >= deadline) {
      timedOut = true;
      break;
    }
    poll(nullptr, 0, 5);
  }
  if (timedOut) {
    kill(child, SIGKILL);
    while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
  }

  outcome.lastWords = lastLine(childStderr);
  if (timedOut) {
    outcome.failure = "ran for more than " + seconds(limits.wallS) + " and was stopped";
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    outcome.succeeded = true;
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == kOutOfMemory) {
    outcome.failure = "needed more than its memory limit of " + mebibytes(limits.memoryBytes);
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == kWorkThrew) {
    outcome.failure = "stopped with an error";
  } else if (WIFEXITED(status)) {
    outcome.failure = "exited with status " + std::to_string(WEXITSTATUS(status));
  } else if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU) {
    outcome.failure = "used more than its " + seconds(std::ceil(std::max(limits.cpuS, 1.0))) + " of CPU time";
  } else if (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) {
    outcome.failure = "was killed by " + describeSignal(SIGKILL) + ", by the CPU limit or the system's out-of-memory killer";
  } else if (WIFSIGNALED(status)) {
    outcome.failure = "was killed by " + describeSignal(WTERMSIG(status));
  } else {
    outcome.failure = "ended in an unknown way (wait status " + std::to_string(status) + ")";
  }
  if (!outcome.succeeded) outcome.result.clear();
  return outcome;
}

}  // namespace firn::voxelizer
