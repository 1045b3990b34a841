#pragma once
// The numeric CSV files BlendBench writes (a header line, then rows of numbers), read back in
// tests.

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace blendbench::test {

struct Csv {
  std::string header;                                   // the first line as written
  std::vector<std::vector<double>> rows;                // every later line, cell by cell
  std::map<std::string, std::vector<double>> columns;  // the same numbers by column name
};

inline Csv parse_csv(const std::string& text) {
  Csv csv;
  std::istringstream in(text);
  std::getline(in, csv.header);
  std::vector<std::string> names;
  std::istringstream head(csv.header);
  for (std::string name; std::getline(head, name, ',');) names.push_back(name);
  for (std::string line; std::getline(in, line);) {
    std::vector<double>& row = csv.rows.emplace_back();
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) {
      row.push_back(std::stod(cell));
      if (row.size() <= names.size()) csv.columns[names[row.size() - 1]].push_back(row.back());
    }
  }
  return csv;
}

inline Csv read_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::ostringstream text;
  text << in.rdbuf();
  return parse_csv(text.str());
}

}  // namespace blendbench::test
