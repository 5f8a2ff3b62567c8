#pragma once
// Reads a CSV file the tools write (a header line, then rows; lines starting with '#'
// are comments) into rows keyed by column name, for tests of what a benchmark wrote.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace arphys::testing {

using CsvRow = std::map<std::string, std::string>;

inline std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// The rows of `path`; a row whose field count differs from the header's is a test failure.
inline std::vector<CsvRow> read_csv(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot read " << path;
  std::vector<std::string> header;
  std::vector<CsvRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> fields = split_csv_line(line);
    if (header.empty()) {
      header = fields;
      continue;
    }
    EXPECT_EQ(fields.size(), header.size()) << path << ": " << line;
    CsvRow row;
    for (std::size_t k = 0; k < header.size() && k < fields.size(); ++k) row[header[k]] = fields[k];
    rows.push_back(std::move(row));
  }
  return rows;
}

// The rows whose column `key` is `value`.
inline std::vector<CsvRow> rows_where(const std::vector<CsvRow>& rows, const std::string& key, const std::string& value) {
  std::vector<CsvRow> out;
  for (const CsvRow& row : rows) {
    const auto it = row.find(key);
    if (it != row.end() && it->second == value) out.push_back(row);
  }
  return out;
}

inline double number(const CsvRow& row, const std::string& key) {
  const auto it = row.find(key);
  EXPECT_NE(it, row.end()) << "no column " << key;
  return it == row.end() ? 0.0 : std::stod(it->second);
}

}  // namespace arphys::testing
