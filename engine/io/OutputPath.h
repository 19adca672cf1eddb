#pragma once
// Checks on an output file's path made before the work that produces the file, so that an hour of simulation is
// not lost to a typo in the path.
#include <filesystem>
#include <string>

namespace firn {

// Throws InputError "<option>: <path>: <problem>" unless a file can be written at `path`: its folder exists and
// this process may write in it (files are written under a temporary name there and renamed), `path` is not a
// folder, and an existing file there may be replaced.
void checkWritableFile(const std::filesystem::path& path, const std::string& option);

}  // namespace firn
