#include "io/AtomicFile.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "Error.h"

namespace firn {

void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes, const std::string& what) {
  std::filesystem::path temporary = path;
  temporary += ".part";
  const auto fail = [&](const std::string& reason) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw InputError(path.string() + ": cannot write " + what + " (" + reason + ")");
  };
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) fail(std::strerror(errno));
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) fail("the write failed; is the disk full?");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) fail(error.message());
}

}  // namespace firn
