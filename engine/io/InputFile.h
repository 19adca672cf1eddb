#pragma once
// Input files read from paths a user gives (scenes, point clouds, checkpoints): regular files only, checked with
// stat before anything is opened, so that a named pipe with no writer cannot block and a device such as /dev/zero
// cannot be read until memory runs out. Every refusal is an InputError naming the file and what is wrong with it.
#include <cstdint>
#include <filesystem>
#include <string>

namespace firn {

// Throws InputError unless `path` is a regular file (or a link to one): "<path>: is a folder, not a <what>",
// "<path>: is not a regular file but a named pipe (FIFO); ...", or "<path>: cannot open <what> (<reason>)".
void requireRegularFile(const std::filesystem::path& path, const std::string& what);

// The whole of a regular file of at most `maxBytes` bytes, read through a descriptor opened without blocking.
// Throws InputError naming the file as requireRegularFile does, and for a file larger than `maxBytes`.
std::string readRegularFile(const std::filesystem::path& path, const std::string& what, std::uintmax_t maxBytes);

}  // namespace firn
