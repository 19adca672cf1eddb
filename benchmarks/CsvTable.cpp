#include "CsvTable.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "io/AtomicFile.h"

namespace firn::bench {

std::string formatNumber(double value) {
  if (!std::isfinite(value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

CsvTable::CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {}

CsvTable::Row& CsvTable::Row::setText(const std::string& column, const std::string& value) {
  // A column the header lacks is a defect in the benchmark, not in its input.
  if (std::find(table_->columns_.begin(), table_->columns_.end(), column) == table_->columns_.end()) {
    throw std::logic_error("CsvTable: no column \"" + column + "\"");
  }
  if (value.find_first_of(",\"\n") == std::string::npos) {
    cells_[column] = value;
    return *this;
  }
  std::string quoted = "\"";
  for (const char c : value) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  cells_[column] = quoted + "\"";
  return *this;
}

CsvTable::Row& CsvTable::Row::set(const std::string& column, double value) { return setText(column, formatNumber(value)); }

CsvTable::Row& CsvTable::Row::setCount(const std::string& column, std::int64_t value) {
  return setText(column, std::to_string(value));
}

CsvTable::Row& CsvTable::addRow() { return rows_.emplace_back(Row(*this)); }

std::string CsvTable::text() const {
  std::string out;
  const auto line = [&](auto cellOf) {
    for (std::size_t i = 0; i < columns_.size(); ++i) out += (i > 0 ? "," : "") + cellOf(columns_[i]);
    out += '\n';
  };
  line([](const std::string& column) { return column; });
  for (const Row& row : rows_) {
    line([&](const std::string& column) {
      const auto cell = row.cells_.find(column);
      return cell == row.cells_.end() ? std::string() : cell->second;
    });
  }
  return out;
}

void CsvTable::write(const std::filesystem::path& path) const { writeFileAtomically(path, text(), "benchmark table"); }

}  // namespace firn::bench
