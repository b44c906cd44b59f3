#include "bouguer/geometry/ply.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/core/csv.h"
#include "bouguer/core/limits.h"

namespace bouguer {
namespace {

enum class Format { ascii, binary_le, binary_be };
enum class Type { int8, uint8, int16, uint16, int32, uint32, float32, float64, none };

Type type_from_name(std::string_view t) {
  if (t == "char" || t == "int8") return Type::int8;
  if (t == "uchar" || t == "uint8") return Type::uint8;
  if (t == "short" || t == "int16") return Type::int16;
  if (t == "ushort" || t == "uint16") return Type::uint16;
  if (t == "int" || t == "int32") return Type::int32;
  if (t == "uint" || t == "uint32") return Type::uint32;
  if (t == "float" || t == "float32") return Type::float32;
  if (t == "double" || t == "float64") return Type::float64;
  return Type::none;
}

std::size_t type_size(Type t) {
  switch (t) {
    case Type::int8: case Type::uint8: return 1;
    case Type::int16: case Type::uint16: return 2;
    case Type::int32: case Type::uint32: case Type::float32: return 4;
    case Type::float64: return 8;
    case Type::none: break;
  }
  return 0;
}

bool is_integer(Type t) { return t != Type::float32 && t != Type::float64; }

struct Property {
  std::string name;
  Type type = Type::none;
  Type count_type = Type::none;  // set for lists
  bool is_list() const { return count_type != Type::none; }
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t pos = 0;
  while (true) {
    while (pos < line.size() && is_space(line[pos])) ++pos;
    if (pos == line.size()) return words;
    const std::size_t start = pos;
    while (pos < line.size() && !is_space(line[pos])) ++pos;
    words.push_back(line.substr(start, pos - start));
  }
}

// The values of the data section, one at a time, in either encoding; every read checks that the
// bytes are there.
class Reader {
 public:
  Reader(std::string_view data, Format format, const std::string& where) : data_(data), format_(format), where_(where) {}

  std::size_t remaining() const { return data_.size() - pos_; }

  // The fewest bytes n values can take: binary, their sizes; ASCII, a digit each and a separator
  // between them.
  std::size_t min_bytes(std::size_t n, Type t) const {
    if (n == 0) return 0;
    return format_ == Format::ascii ? 2 * n - 1 : n * type_size(t);
  }

  double read(Type type) {
    if (format_ == Format::ascii) return read_ascii();
    const std::size_t n = type_size(type);
    if (remaining() < n) fail("{}: the PLY data ends early", where_);
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    if ((format_ == Format::binary_be) == (std::endian::native == std::endian::little)) std::reverse(b, b + n);
    return decode(type, b);
  }

 private:
  double read_ascii() {
    while (pos_ < data_.size() && is_space(data_[pos_])) ++pos_;
    const std::size_t start = pos_;
    while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
    const std::string_view word = data_.substr(start, pos_ - start);
    if (word.empty()) fail("{}: the PLY data ends early", where_);
    double v = 0.0;
    const char* first = word.data() + (word.front() == '+' ? 1 : 0);
    const auto [ptr, ec] = std::from_chars(first, word.data() + word.size(), v);
    if (ec != std::errc() || ptr != word.data() + word.size())
      fail("{}: the PLY data holds '{}' where a number belongs", where_, excerpt(word));
    return v;
  }

  static double decode(Type t, const unsigned char* b) {
    auto get = [&](auto v) {
      std::memcpy(&v, b, sizeof v);
      return static_cast<double>(v);
    };
    switch (t) {
      case Type::int8: return get(std::int8_t{});
      case Type::uint8: return get(std::uint8_t{});
      case Type::int16: return get(std::int16_t{});
      case Type::uint16: return get(std::uint16_t{});
      case Type::int32: return get(std::int32_t{});
      case Type::uint32: return get(std::uint32_t{});
      case Type::float32: return get(float{});
      case Type::float64: case Type::none: break;
    }
    return get(double{});
  }

  std::string_view data_;
  std::size_t pos_ = 0;
  Format format_;
  const std::string& where_;
};

struct Header {
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::size_t data_offset = 0;
};

Header parse_header(std::string_view bytes, const std::string& where) {
  if (!bytes.starts_with("ply\n") && !bytes.starts_with("ply\r\n")) fail("{}: not a PLY file", where);
  Header h;
  bool format_seen = false;
  std::size_t pos = 0;
  for (int line_number = 1;; ++line_number) {
    if (pos >= bytes.size()) fail("{}: the PLY header has no 'end_header' line", where);
    const std::size_t newline = bytes.find('\n', pos);
    const std::string_view line = bytes.substr(pos, newline == std::string_view::npos ? bytes.size() - pos : newline - pos);
    pos = newline == std::string_view::npos ? bytes.size() : newline + 1;
    const std::vector<std::string_view> w = words_of(line);
    const auto bad = [&](std::string_view why) {
      fail("{}: PLY header line {} '{}': {}", where, line_number, excerpt(line), why);
    };
    if (line_number == 1 || w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      if (!format_seen) fail("{}: the PLY header has no 'format' line", where);
      h.data_offset = pos;
      return h;
    }
    if (w[0] == "format") {
      if (w.size() != 3) bad("expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
      if (w[1] == "ascii") h.format = Format::ascii;
      else if (w[1] == "binary_little_endian") h.format = Format::binary_le;
      else if (w[1] == "binary_big_endian") h.format = Format::binary_be;
      else bad("unknown format");
      format_seen = true;
    } else if (w[0] == "element") {
      Element e;
      std::uint64_t count = 0;
      if (w.size() != 3) bad("expected 'element <name> <count>'");
      const auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), count);
      if (ec != std::errc() || ptr != w[2].data() + w[2].size()) bad("the count is not a whole number");
      if (count > std::max(kMaxMeshVertices, kMaxMeshTriangles))
        bad(fmt::format("more than {} elements (docs/limits.md)", std::max(kMaxMeshVertices, kMaxMeshTriangles)));
      e.name = std::string(w[1]);
      e.count = static_cast<std::size_t>(count);
      h.elements.push_back(std::move(e));
    } else if (w[0] == "property") {
      if (h.elements.empty()) bad("a property before any element");
      Property p;
      if (w.size() == 5 && w[1] == "list") {
        p.count_type = type_from_name(w[2]);
        p.type = type_from_name(w[3]);
        if (p.count_type == Type::none || p.type == Type::none) bad("unknown property type");
        if (!is_integer(p.count_type)) bad("a list count must have an integer type");
      } else if (w.size() == 3) {
        p.type = type_from_name(w[1]);
        if (p.type == Type::none) bad("unknown property type");
      } else {
        bad("expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      }
      p.name = std::string(w.back());
      h.elements.back().properties.push_back(std::move(p));
    } else {
      bad("not a PLY header line");
    }
  }
}

// The whole number `v` as a list count or vertex index, or an Error naming what it is.
std::uint32_t whole_number(double v, const std::string& where, const Element& e, std::size_t i, const char* what) {
  if (!(v >= 0.0 && v <= 4294967295.0) || v != std::floor(v))
    fail("{}: {} {}: {} {} is not a whole number from 0 to 4294967295", where, excerpt(e.name), i, what, v);
  return static_cast<std::uint32_t>(v);
}

}  // namespace

Mesh load_ply(const std::filesystem::path& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail("{}: mesh file '{}' not found", what, path.string());
  const std::string where = what + ": " + path.string();
  std::string bytes;
  try {
    bytes = read_file_bytes(path, kMaxMeshFileBytes);
  } catch (const Error& e) {
    fail("{}: {}", what, e.what());
  }
  const Header header = parse_header(bytes, where);
  Reader reader(std::string_view(bytes).substr(header.data_offset), header.format, where);

  // Every element's values must fit in the bytes that follow the header before any is read.
  std::size_t values = 0, fixed_bytes = 0;
  for (const Element& e : header.elements) {
    for (const Property& p : e.properties) {
      values += e.count;
      fixed_bytes += e.count * type_size(p.is_list() ? p.count_type : p.type);
    }
  }
  const std::size_t needed = header.format == Format::ascii ? (values == 0 ? 0 : 2 * values - 1) : fixed_bytes;
  if (needed > reader.remaining())
    fail("{}: the PLY header declares elements of at least {} bytes, but only {} bytes follow it", where, needed,
         reader.remaining());

  for (const Element& e : header.elements) {
    if (e.name != "vertex") continue;
    for (const char* axis : {"x", "y", "z"})
      if (std::none_of(e.properties.begin(), e.properties.end(),
                       [&](const Property& p) { return p.name == axis && !p.is_list(); }))
        fail("{}: the PLY vertex element has no '{}' property", where, axis);
  }

  Mesh m;
  for (const Element& e : header.elements) {
    if (e.properties.empty()) continue;  // nothing in the data
    const bool vertex = e.name == "vertex", face = e.name == "face";
    if (vertex && m.positions.size() + e.count > kMaxMeshVertices)
      fail("{}: more than {} vertices (docs/limits.md)", where, kMaxMeshVertices);
    if (vertex) m.positions.reserve(m.positions.size() + e.count);
    for (std::size_t i = 0; i < e.count; ++i) {
      Vec3 p;
      for (const Property& prop : e.properties) {
        if (!prop.is_list()) {
          const double v = reader.read(prop.type);
          const int axis = prop.name == "x" ? 0 : prop.name == "y" ? 1 : prop.name == "z" ? 2 : -1;
          if (!vertex || axis < 0) continue;
          if (!std::isfinite(v)) fail("{}: vertex {}: {} is {}, not a finite number", where, i, prop.name, v);
          if (std::abs(v) > kMaxMeshCoordinate)
            fail("{}: vertex {}: {} = {} is beyond ±{} (docs/limits.md)", where, i, prop.name, v, kMaxMeshCoordinate);
          p[static_cast<std::size_t>(axis)] = v;
          continue;
        }
        const std::uint32_t n = whole_number(reader.read(prop.count_type), where, e, i, "list count");
        if (reader.min_bytes(n, prop.type) > reader.remaining())
          fail("{}: {} {}: a list of {} entries, but only {} bytes follow", where, excerpt(e.name), i, n,
               reader.remaining());
        const bool indices = face && (prop.name == "vertex_indices" || prop.name == "vertex_index");
        if (indices && n >= 3 && m.triangles.size() + (n - 2) > kMaxMeshTriangles)
          fail("{}: more than {} triangles (docs/limits.md)", where, kMaxMeshTriangles);
        // Polygons are fan-triangulated as they are read: (first, previous, this).
        std::uint32_t first = 0, previous = 0;
        for (std::uint32_t k = 0; k < n; ++k) {
          const double v = reader.read(prop.type);
          if (!indices) continue;
          const std::uint32_t index = whole_number(v, where, e, i, "vertex index");
          if (k >= 2) m.triangles.push_back({first, previous, index});
          if (k == 0) first = index;
          previous = index;
        }
      }
      if (vertex) m.positions.push_back(p);
    }
  }
  for (const auto& t : m.triangles)
    for (auto k : t)
      if (k >= m.positions.size()) fail("{}: a face refers to vertex {} of {}", where, k, m.positions.size());
  if (m.triangles.empty()) fail("{}: no faces", where);
  return m;
}

}  // namespace bouguer
