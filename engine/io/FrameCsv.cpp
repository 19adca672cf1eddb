#include "io/FrameCsv.h"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <system_error>

#include "Error.h"
#include "io/AtomicFile.h"
#include "io/InputFile.h"

namespace firn {

FrameCsv::FrameCsv(const std::filesystem::path& path, const std::string& header, const std::string& what)
    : path_(path), what_(what) {
  start(header);
}

FrameCsv::FrameCsv(const std::filesystem::path& path, const std::string& header, const std::string& what,
                   int firstFrame)
    : path_(path), what_(what) {
  std::error_code error;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, error))) {
    start(header);
    return;
  }
  requireRegularFile(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot read " + what + " (" + std::strerror(errno) + ")");
  std::string line;
  int lineNumber = 1;
  std::getline(in, line);
  if (line != header) {
    throw InputError(path.string() + ": its header is not the one this version of Firn writes, so its rows before "
                     "frame " + std::to_string(firstFrame) + " cannot be kept; move it away to resume without them");
  }
  for (++lineNumber; std::getline(in, line); ++lineNumber) {
    // A last line without its line break is a row cut short by a run that was killed while writing it.
    if (in.eof()) break;
    int frame = 0;
    const auto [end, parseError] = std::from_chars(line.data(), line.data() + line.size(), frame);
    if (parseError != std::errc() || end == line.data() + line.size() || *end != ',') {
      throw InputError(path.string() + ": line " + std::to_string(lineNumber) +
                       ": no frame number, so the rows before frame " + std::to_string(firstFrame) +
                       " cannot be kept; move it away to resume without them");
    }
    if (frame < firstFrame) keptRows_ += line + '\n';
  }
  if (in.bad()) throw InputError(path.string() + ": cannot read " + what + " (" + std::strerror(errno) + ")");
  in.close();
  start(header);
}

void FrameCsv::start(const std::string& header) {
  writeFileAtomically(path_, header + '\n' + keptRows_, what_);
  out_.open(path_, std::ios::app);
  if (!out_) throw InputError(path_.string() + ": cannot write " + what_ + " (" + std::strerror(errno) + ")");
}

void FrameCsv::append(const std::string& rows) {
  out_ << rows;
  out_.flush();
  if (!out_) throw InputError(path_.string() + ": writing the " + what_ + " failed (disk full?)");
}

}  // namespace firn
