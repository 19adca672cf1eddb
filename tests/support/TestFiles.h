#pragma once
// Folders and files for the tests that write them (unit and GL tests alike).
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace firn::test {

// An empty folder of the system's temporary one, named for the test; the process id keeps concurrent test runs
// (ctest --parallel, two checkouts) out of each other's way.
inline std::filesystem::path freshDirectory(const std::string& name) {
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("firn_test_" + std::to_string(getpid()) + "_" + name);
  std::filesystem::remove_all(directory);
  std::filesystem::create_directories(directory);
  return directory;
}

inline std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace firn::test
