#pragma once
// Output files that a reader never sees half-written.
#include <filesystem>
#include <string>

namespace firn {

// Writes `bytes` to `path` through `path` + ".part" and a rename. Throws InputError naming the file, with
// `what` ("point cache", "PNG") and the system's reason, if it cannot be written; the partial file is removed.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes, const std::string& what);

}  // namespace firn
