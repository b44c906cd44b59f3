#include "bouguer/core/csv.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"

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
        fail("{}, line {}: column '{}': '{}' is not a number", source, line_number, excerpt(table.columns[i]),
             excerpt(cells[i]));
    }
    table.rows.push_back(std::move(row));
    table.line.push_back(line_number);
  }
  if (table.columns.empty()) fail("{}: empty file (no header row, no data)", source);
  if (table.rows.empty()) fail("{}: no data rows after the header", source);
  return table;
}

namespace {

std::string mebibytes(std::uintmax_t bytes) {
  if (bytes < (1u << 20)) return fmt::format("{} bytes", bytes);
  return fmt::format("{:.1f} MiB", static_cast<double>(bytes) / static_cast<double>(1 << 20));
}

// What `st` is must be a regular file of at most max_bytes; anything else is an Error naming it.
void check_kind_and_size(const struct stat& st, const std::string& name, std::uintmax_t max_bytes) {
  if (S_ISDIR(st.st_mode)) fail("{}: is a folder, not a file", name);
  if (!S_ISREG(st.st_mode))
    fail("{}: is not a regular file (a device, FIFO or socket); give the path of a file", name);
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes)
    fail("{}: the file has {}, more than the {} this kind of file may have (docs/limits.md)", name,
         mebibytes(static_cast<std::uintmax_t>(st.st_size)), mebibytes(max_bytes));
}

struct stat stat_or_fail(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT || errno == ENOTDIR) fail("{}: file not found", path.string());
    fail("{}: cannot open for reading ({})", path.string(), std::strerror(errno));
  }
  return st;
}

class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

std::uintmax_t require_regular_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  const struct stat st = stat_or_fail(path);
  check_kind_and_size(st, path.string(), max_bytes);
  return static_cast<std::uintmax_t>(st.st_size);
}

std::string read_file_bytes(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  const std::string name = path.string();
  // Checked before opening (opening a device can do things) and again through the descriptor,
  // in case the path changed in between. O_NONBLOCK: opening a FIFO must not wait for a writer.
  require_regular_file(path, max_bytes);
  const Descriptor fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
  if (fd.get() < 0) fail("{}: cannot open for reading ({})", name, std::strerror(errno));
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) fail("{}: cannot open for reading ({})", name, std::strerror(errno));
  check_kind_and_size(st, name, max_bytes);
  // The size may change while we read: read to the end, never past the limit.
  std::string bytes(static_cast<std::size_t>(st.st_size) + 1, '\0');
  std::size_t used = 0;
  while (true) {
    if (used == bytes.size()) {
      if (used > max_bytes)
        fail("{}: the file grew past the {} this kind of file may have while it was read (docs/limits.md)", name,
             mebibytes(max_bytes));
      bytes.resize(static_cast<std::size_t>(std::min<std::uintmax_t>(2 * used + 4096, max_bytes + 1)));
    }
    const ssize_t n = ::read(fd.get(), bytes.data() + used, bytes.size() - used);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail("{}: read error ({})", name, std::strerror(errno));
    if (n == 0) break;
    used += static_cast<std::size_t>(n);
  }
  bytes.resize(used);
  return bytes;
}

std::string read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  std::string text = read_file_bytes(path, max_bytes);
  if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);
  return text;
}

CsvTable read_csv_file(const std::filesystem::path& path) {
  return parse_csv(read_text_file(path), path.string());
}

}  // namespace bouguer
