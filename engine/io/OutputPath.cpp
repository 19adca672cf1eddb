#include "io/OutputPath.h"

#include <unistd.h>

#include <system_error>

#include "Error.h"

namespace firn {

void checkWritableFile(const std::filesystem::path& path, const std::string& option) {
  namespace fs = std::filesystem;
  const auto refuse = [&](const std::string& problem) {
    throw InputError(option + ": " + path.string() + ": " + problem);
  };
  std::error_code error;
  if (path.empty()) throw InputError(option + ": the path is empty");
  if (fs::is_directory(path, error)) refuse("is a folder; give a file name in it");
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::exists(folder, error)) refuse("the folder " + folder.string() + " does not exist");
  if (!fs::is_directory(folder, error)) refuse(folder.string() + " is not a folder");
  if (access(folder.c_str(), W_OK | X_OK) != 0) refuse("this process may not write in the folder " + folder.string());
  if (fs::exists(path, error) && access(path.c_str(), W_OK) != 0) refuse("exists and may not be replaced (read-only)");
}

}  // namespace firn
