#pragma once
// The one CSV writer for result files (path.csv, program.csv, the timed profile, trace.csv): a
// header of column names, then rows of numbers, each with kCsvDigits significant digits in the
// shortest form (format_value, core/format.hpp), "nan"/"inf" for non-finite values.

#include <initializer_list>
#include <span>
#include <string>
#include <vector>

namespace blendbench {

// Significant digits of every number in a CSV file: enough for micrometres on metre-sized paths
// in mm (1e-9 relative) and for the 1 ms grid of times.
inline constexpr int kCsvDigits = 12;

class CsvWriter {
 public:
  // The column names; rows must have as many values (asserted).
  explicit CsvWriter(std::vector<std::string> columns);

  [[nodiscard]] std::size_t columns() const { return columns_; }
  // Reserves space for about `rows` rows.
  void reserve(std::size_t rows);
  void row(std::span<const double> values);
  void row(std::initializer_list<double> values) { row(std::span<const double>(values.begin(), values.size())); }
  // The file's text: the header line and every row, each ending in '\n'.
  [[nodiscard]] const std::string& text() const { return text_; }

 private:
  std::size_t columns_;
  std::string text_;
};

}  // namespace blendbench
