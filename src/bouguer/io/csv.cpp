#include "bouguer/io/csv.h"

#include <charconv>
#include <fstream>
#include <sstream>

#include "bouguer/core/error.h"

namespace bouguer {
namespace {

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

bool parse_number(std::string_view cell, double& out) {
  if (!cell.empty() && cell.front() == '+') cell.remove_prefix(1);
  const auto* end = cell.data() + cell.size();
  const auto [ptr, ec] = std::from_chars(cell.data(), end, out);
  return ec == std::errc() && ptr == end && !cell.empty();
}

}  // namespace

CsvTable parse_csv(std::string_view text, const std::string& source) {
  CsvTable table;
  table.source = source;
  int line_number = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const auto newline = text.find('\n', pos);
    const std::string_view line = trim(text.substr(pos, newline - pos));
    pos = newline == std::string_view::npos ? text.size() + 1 : newline + 1;
    ++line_number;
    if (line.empty() || line.front() == '#') continue;
    const auto cells = split_cells(line);
    if (table.columns.empty()) {
      double ignored = 0.0;
      if (parse_number(cells.front(), ignored))
        fail("{}, line {}: expected a header row naming the columns (e.g. 'wavelength_nm,value'), found numbers",
             source, line_number);
      for (const auto c : cells) table.columns.emplace_back(c);
      continue;
    }
    if (cells.size() != table.columns.size())
      fail("{}, line {}: {} cells, but the header names {} columns", source, line_number, cells.size(),
           table.columns.size());
    std::vector<double> row(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (!parse_number(cells[i], row[i]))
        fail("{}, line {}: column '{}': '{}' is not a number", source, line_number, table.columns[i], cells[i]);
    }
    table.rows.push_back(std::move(row));
    table.line.push_back(line_number);
  }
  if (table.columns.empty()) fail("{}: empty file (no header row, no data)", source);
  if (table.rows.empty()) fail("{}: no data rows after the header", source);
  return table;
}

std::string read_text_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail("{}: file not found", path.string());
  if (std::filesystem::is_directory(path, ec)) fail("{}: is a folder, not a file", path.string());
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("{}: cannot open for reading", path.string());
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) fail("{}: read error", path.string());
  return buffer.str();
}

CsvTable read_csv_file(const std::filesystem::path& path) {
  return parse_csv(read_text_file(path), path.string());
}

}  // namespace bouguer
