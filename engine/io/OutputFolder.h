#pragma once
// An output folder held by one process at a time. Two runs writing into one folder glue their stats rows together
// and overwrite each other's frames, so a run claims its folder before it writes there: an exclusive flock(2) on
// DIR/.firn-lock. The kernel drops the lock when the process ends, however it ends (SIGKILL included), so a claim
// is never stale: the lock file a killed run leaves behind is taken over by the next claim. A claim that ends
// normally removes the file. The process id in it only names the holder in the message of a refused claim.
#include <filesystem>

namespace firn {

class OutputFolderClaim {
 public:
  // Creates `folder` if missing and claims it. Throws InputError naming the folder if it cannot be created or
  // another process holds it ("<folder>: output folder in use by another firn (process P) ...").
  explicit OutputFolderClaim(const std::filesystem::path& folder);
  OutputFolderClaim(const OutputFolderClaim&) = delete;
  OutputFolderClaim& operator=(const OutputFolderClaim&) = delete;
  ~OutputFolderClaim();  // releases the claim

  static constexpr const char* kLockFileName = ".firn-lock";

 private:
  std::filesystem::path lockPath_;
  int lockFile_ = -1;
};

}  // namespace firn
