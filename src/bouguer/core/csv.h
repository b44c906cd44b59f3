#pragma once
// Numeric CSV tables: '#' comment lines and blank lines are skipped, the first other line is the
// header (column names), every later line holds one number per column. Errors name the source and
// the line ("red.csv, line 7: ...").
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "bouguer/core/limits.h"

namespace bouguer {

struct CsvTable {
  std::string source;                     // file name (or data set name) for messages
  std::vector<std::string> columns;       // header names
  std::vector<std::vector<double>> rows;  // rows[i][column]; NaN where the cell said "nan"
  std::vector<int> line;                  // 1-based line number of rows[i] in the source
};

CsvTable parse_csv(std::string_view text, const std::string& source);
CsvTable read_csv_file(const std::filesystem::path& path);

// The whole file, at most max_bytes. Errors name it: missing, unreadable, larger than the limit,
// or not a regular file (a folder, FIFO, device or socket is refused before a byte is read).
std::string read_file_bytes(const std::filesystem::path& path, std::uintmax_t max_bytes);

// The same for text: a leading UTF-8 byte-order mark (spreadsheets write one) is dropped.
std::string read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes = kMaxTextFileBytes);

// For readers that open files themselves (OpenEXR): the same checks, without reading. Returns
// the size in bytes.
std::uintmax_t require_regular_file(const std::filesystem::path& path, std::uintmax_t max_bytes);

}  // namespace bouguer
