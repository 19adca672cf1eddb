#include "io/OutputFolder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "Error.h"

namespace firn {
namespace {

// The process id the holder wrote into the lock file, or "" if it has not written it yet.
std::string holderOf(int lockFile) {
  char text[32] = {};
  const ssize_t count = ::pread(lockFile, text, sizeof text - 1, 0);
  if (count <= 0) return "";
  std::string pid(text, std::size_t(count));
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid;
}

}  // namespace

OutputFolderClaim::OutputFolderClaim(const std::filesystem::path& folder) : lockPath_(folder / kLockFileName) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw InputError(folder.string() + ": cannot create output folder (" + error.message() + ")");
  const auto cannot = [&](const std::string& what, int reason) {
    return InputError(folder.string() + ": cannot claim output folder: cannot " + what + " " + lockPath_.string() +
                      " (" + std::strerror(reason) + ")");
  };
  while (true) {
    // O_CLOEXEC: a program the run starts (ffmpeg) must not inherit the lock and hold the folder after the run.
    lockFile_ = ::open(lockPath_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lockFile_ < 0) throw cannot("open", errno);
    int result;
    do {
      result = ::flock(lockFile_, LOCK_EX | LOCK_NB);
    } while (result != 0 && errno == EINTR);
    if (result != 0) {
      const int reason = errno;
      const std::string holder = reason == EWOULDBLOCK ? holderOf(lockFile_) : "";
      ::close(lockFile_);
      lockFile_ = -1;
      if (reason != EWOULDBLOCK) throw cannot("lock", reason);
      throw InputError(folder.string() + ": output folder in use by another firn" +
                       (holder.empty() ? std::string() : " (process " + holder + ")") +
                       "; wait for it to end or give another --out");
    }
    // A holder removes the file before it lets go (the destructor): if it did so between this open and this lock,
    // the lock is on a file no longer in the folder, and the claim starts again with the folder's own file.
    struct stat locked {}, named {};
    if (::fstat(lockFile_, &locked) == 0 && ::stat(lockPath_.c_str(), &named) == 0 && locked.st_dev == named.st_dev &&
        locked.st_ino == named.st_ino) {
      break;
    }
    ::close(lockFile_);
  }
  // The process id only names the holder in the message of a refused claim: failing to write it changes nothing
  // about the claim.
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(lockFile_, 0) == 0) {
    [[maybe_unused]] const ssize_t written = ::pwrite(lockFile_, pid.data(), pid.size(), 0);
  }
}

OutputFolderClaim::~OutputFolderClaim() {
  if (lockFile_ < 0) return;
  // Removed while still locked, so that no other claim can have locked this file meanwhile (see the constructor).
  ::unlink(lockPath_.c_str());
  ::close(lockFile_);
}

}  // namespace firn
