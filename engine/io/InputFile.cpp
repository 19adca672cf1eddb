#include "io/InputFile.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "Error.h"

namespace firn {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) {
  throw InputError(path.string() + ": " + problem);
}

// What a file that is not regular is, for the message.
const char* kindOf(mode_t mode) {
  if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "neither a file nor a folder";
}

void requireRegular(const std::filesystem::path& path, const std::string& what, mode_t mode) {
  if (S_ISDIR(mode)) fail(path, "is a folder, not a " + what);
  if (!S_ISREG(mode)) {
    fail(path, std::string("is not a regular file but ") + kindOf(mode) + "; a " + what +
                   " is read from a regular file only");
  }
}

// Closes the descriptor on every way out of readRegularFile.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

void requireRegularFile(const std::filesystem::path& path, const std::string& what) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) fail(path, "cannot open " + what + " (" + std::strerror(errno) + ")");
  requireRegular(path, what, status.st_mode);
}

std::string readRegularFile(const std::filesystem::path& path, const std::string& what, std::uintmax_t maxBytes) {
  requireRegularFile(path, what);
  // O_NONBLOCK: should the path have become a named pipe since the stat, the open returns at once instead of
  // waiting for a writer, and the fstat below refuses it.
  const Descriptor file(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (file.get() < 0) fail(path, "cannot open " + what + " (" + std::strerror(errno) + ")");
  struct stat status {};
  if (::fstat(file.get(), &status) != 0) fail(path, "cannot open " + what + " (" + std::strerror(errno) + ")");
  requireRegular(path, what, status.st_mode);
  const auto tooLarge = [&](std::uintmax_t bytes) {
    fail(path, "is " + std::to_string(bytes) + " bytes, more than the " + std::to_string(maxBytes) + " a " + what +
                   " may have");
  };
  if (std::uintmax_t(status.st_size) > maxBytes) tooLarge(std::uintmax_t(status.st_size));
  std::string bytes;
  bytes.reserve(std::size_t(status.st_size));
  char buffer[1 << 16];
  while (true) {
    const ssize_t count = ::read(file.get(), buffer, sizeof buffer);
    if (count < 0 && errno == EINTR) continue;
    if (count < 0) fail(path, "cannot read " + what + " (" + std::strerror(errno) + ")");
    if (count == 0) break;
    bytes.append(buffer, std::size_t(count));
    // A file still growing as it is read is held to the same limit.
    if (bytes.size() > maxBytes) tooLarge(bytes.size());
  }
  return bytes;
}

}  // namespace firn
