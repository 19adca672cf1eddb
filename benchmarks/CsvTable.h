#pragma once
// The benchmark tables: a header row and one row per configuration, written atomically. Numbers get six
// significant digits, counts all of theirs; a value that is not finite becomes an empty cell, so no table
// ever holds a NaN. Text with a comma or a quote (renderer names do: "llvmpipe (LLVM 15.0.6, 256 bits)") is
// quoted as RFC 4180 says.
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace firn::bench {

class CsvTable {
 public:
  explicit CsvTable(std::vector<std::string> columns);

  // A new row; its cells are set by column name and those left unset stay empty.
  class Row {
   public:
    Row& set(const std::string& column, double value);
    Row& setCount(const std::string& column, std::int64_t value);
    Row& setText(const std::string& column, const std::string& value);

   private:
    friend class CsvTable;
    explicit Row(const CsvTable& table) : table_(&table) {}
    const CsvTable* table_;
    std::map<std::string, std::string> cells_;
  };
  Row& addRow();

  std::string text() const;
  // Through writeFileAtomically: throws InputError naming the file if it cannot be written.
  void write(const std::filesystem::path& path) const;

 private:
  std::vector<std::string> columns_;
  std::deque<Row> rows_;  // a deque: addRow's references stay valid
};

// Six significant digits (printf's %.6g), or "" for a value that is not finite.
std::string formatNumber(double value);

}  // namespace firn::bench
