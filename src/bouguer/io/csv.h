#pragma once
// Numeric CSV tables: '#' comment lines and blank lines are skipped, the first other line is the
// header (column names), every later line holds one number per column. Errors name the source and
// the line ("red.csv, line 7: ...").
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace bouguer {

struct CsvTable {
  std::string source;                     // file name (or data set name) for messages
  std::vector<std::string> columns;       // header names
  std::vector<std::vector<double>> rows;  // rows[i][column]; NaN where the cell said "nan"
  std::vector<int> line;                  // 1-based line number of rows[i] in the source
};

CsvTable parse_csv(std::string_view text, const std::string& source);
CsvTable read_csv_file(const std::filesystem::path& path);

// The whole file as text; a missing or unreadable file is an Error naming it.
std::string read_text_file(const std::filesystem::path& path);

}  // namespace bouguer
