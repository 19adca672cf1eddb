#include "HeadlessJob.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <regex>
#include <stdexcept>

extern char** environ;

namespace firn {
namespace {

// This executable, which runs the scene as `firn run` would.
std::string ownExecutable() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string("firn") : self.string();
}

}  // namespace

HeadlessJob::HeadlessJob(const std::filesystem::path& scene, const std::filesystem::path& outputDir)
    : outputDir_(outputDir) {
  int pipeEnds[2];
  // Close-on-exec: the run takes its own ends (the file actions' dup2), no other child takes any.
  if (pipe2(pipeEnds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("no pipe: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipeEnds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, pipeEnds[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipeEnds[0]);
  posix_spawn_file_actions_addclose(&actions, pipeEnds[1]);
  const std::string executable = ownExecutable();
  const std::string scenePath = scene.string(), outputPath = outputDir.string();
  std::vector<char*> arguments = {const_cast<char*>(executable.c_str()), const_cast<char*>("run"),
                                  const_cast<char*>(scenePath.c_str()), const_cast<char*>("--out"),
                                  const_cast<char*>(outputPath.c_str()), nullptr};
  // The environment as it is, with progress lines twice a second.
  std::vector<std::string> variables;
  for (char** variable = environ; *variable != nullptr; ++variable) {
    if (std::strncmp(*variable, "FIRN_PROGRESS_INTERVAL_S=", 25) != 0) variables.emplace_back(*variable);
  }
  variables.emplace_back("FIRN_PROGRESS_INTERVAL_S=0.5");
  std::vector<char*> environment;
  for (std::string& variable : variables) environment.push_back(variable.data());
  environment.push_back(nullptr);
  const int spawned = posix_spawn(&pid_, executable.c_str(), &actions, nullptr, arguments.data(), environment.data());
  posix_spawn_file_actions_destroy(&actions);
  close(pipeEnds[1]);
  if (spawned != 0) {
    close(pipeEnds[0]);
    throw std::runtime_error("could not start " + executable + ": " + std::strerror(spawned));
  }
  output_ = pipeEnds[0];
  fcntl(output_, F_SETFL, fcntl(output_, F_GETFL) | O_NONBLOCK);
}

HeadlessJob::~HeadlessJob() {
  stop();
  wait();
}

void HeadlessJob::take(const std::string& line) {
  lines_.push_back(line);
  // "firn: frame 12/36  t = …", and "firn: wrote 36 frames …" at the end.
  static const std::regex frame(R"(frame ([0-9]+)/([0-9]+))");
  std::smatch match;
  if (std::regex_search(line, match, frame) && std::stod(match[2]) > 0) {
    fraction_ = std::stod(match[1]) / std::stod(match[2]);
  }
  if (line.rfind("firn: wrote ", 0) == 0) fraction_ = 1;
}

void HeadlessJob::readOutput() {
  if (output_ < 0) return;
  char buffer[4096];
  for (;;) {
    const ssize_t count = read(output_, buffer, sizeof buffer);
    if (count > 0) {
      partial_.append(buffer, std::size_t(count));
      continue;
    }
    if (count == 0 || errno != EAGAIN) {  // the run closed its output (it is ending), or it cannot be read
      close(output_);
      output_ = -1;
    }
    break;
  }
  for (std::size_t end; (end = partial_.find('\n')) != std::string::npos; partial_.erase(0, end + 1)) {
    take(partial_.substr(0, end));
  }
}

void HeadlessJob::poll() {
  readOutput();
  if (exitCode_ || pid_ < 0) return;
  int status = 0;
  const pid_t waited = waitpid(pid_, &status, WNOHANG);
  if (waited == 0) return;
  // Ended (or no longer this process's child: its status is lost). What it wrote before it ended is all in the pipe
  // now, its last line (a pipe's stdout is flushed at exit) with it: read to the end before saying it ended.
  exitCode_ = waited == pid_ ? (WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)) : 255;
  readOutput();
  if (!partial_.empty()) take(partial_);
  partial_.clear();
}

void HeadlessJob::wait() {
  while (running() || output_ >= 0) {
    if (output_ >= 0) {
      pollfd ready{output_, POLLIN, 0};
      ::poll(&ready, 1, 100);
    } else {
      usleep(10000);
    }
    poll();
  }
}

void HeadlessJob::stop() {
  if (running() && pid_ > 0) kill(pid_, SIGTERM);
}

}  // namespace firn
