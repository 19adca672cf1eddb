#pragma once
// A CSV file of rows per frame (stats.csv, bodies.csv): plain CSV, a header, then rows that begin with their frame
// number, flushed as they are written so a stopped run keeps its rows, and continued by a run resumed from a
// checkpoint.
#include <filesystem>
#include <fstream>
#include <string>

namespace firn {

class FrameCsv {
 public:
  // Starts the file afresh with its header. `what` names the file in messages ("stats file"). Throws InputError
  // naming the file if it cannot be written.
  FrameCsv(const std::filesystem::path& path, const std::string& header, const std::string& what);
  // Continues the file of a run resumed at `firstFrame`: keeps its rows of the frames before it and drops the rest,
  // which the resumed run writes again. The kept rows replace the file atomically (io/AtomicFile.h), so a run stopped
  // here leaves the old file or the new one. A missing file starts afresh. Throws InputError naming the file if it
  // cannot be read or written, has another header than `header` or holds a row without a frame number.
  FrameCsv(const std::filesystem::path& path, const std::string& header, const std::string& what, int firstFrame);

  // The rows kept from before the resumed run's first frame, each ending in a line break; empty for a fresh file.
  const std::string& keptRows() const { return keptRows_; }
  // Appends `rows` (whole lines) and flushes them. Throws InputError naming the file if writing fails.
  void append(const std::string& rows);

 private:
  // Writes the header and `keptRows_` to the file atomically, then opens it to append.
  void start(const std::string& header);

  std::filesystem::path path_;
  std::string what_;
  std::string keptRows_;
  std::ofstream out_;
};

}  // namespace firn
