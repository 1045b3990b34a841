#include "blendbench/report/csv.hpp"

#include <cassert>

#include "blendbench/report/output.hpp"

namespace blendbench {

CsvWriter::CsvWriter(std::vector<std::string> columns) : columns_(columns.size()) {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) text_ += ',';
    text_ += columns[i];
  }
  text_ += '\n';
}

void CsvWriter::reserve(std::size_t rows) { text_.reserve(text_.size() + rows * columns_ * (kCsvDigits + 2)); }

void CsvWriter::row(std::span<const double> values) {
  assert(values.size() == columns_);
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) text_ += ',';
    text_ += format_value(values[i], kCsvDigits);
  }
  text_ += '\n';
}

}  // namespace blendbench
