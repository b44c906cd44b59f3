#include "bouguer/geometry/ply.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <sstream>

#include "bouguer/core/error.h"
#include "bouguer/io/csv.h"

namespace bouguer {
namespace {

enum class Format { ascii, binary_le, binary_be };

struct Property {
  std::string name, type, count_type;  // count_type non-empty for lists
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
};

std::size_t type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

class Reader {
 public:
  Reader(const std::string& bytes, std::size_t offset, Format format, const std::string& where)
      : bytes_(bytes), pos_(offset), format_(format), where_(where), text_(bytes.substr(offset)) {}

  double read(const std::string& type) {
    if (format_ == Format::ascii) {
      double v = 0.0;
      if (!(text_ >> v)) fail("{}: PLY data ends early or holds a non-number", where_);
      return v;
    }
    const std::size_t n = type_size(type);
    if (pos_ + n > bytes_.size()) fail("{}: PLY data ends early", where_);
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, n);
    pos_ += n;
    if ((format_ == Format::binary_be) == (std::endian::native == std::endian::little)) std::reverse(b, b + n);
    return decode(type, b);
  }

 private:
  static double decode(const std::string& t, const unsigned char* b) {
    auto get = [&](auto v) { std::memcpy(&v, b, sizeof v); return static_cast<double>(v); };
    if (t == "char" || t == "int8") return get(std::int8_t{});
    if (t == "uchar" || t == "uint8") return get(std::uint8_t{});
    if (t == "short" || t == "int16") return get(std::int16_t{});
    if (t == "ushort" || t == "uint16") return get(std::uint16_t{});
    if (t == "int" || t == "int32") return get(std::int32_t{});
    if (t == "uint" || t == "uint32") return get(std::uint32_t{});
    if (t == "float" || t == "float32") return get(float{});
    return get(double{});
  }

  const std::string& bytes_;
  std::size_t pos_;
  Format format_;
  std::string where_;
  std::istringstream text_;
};

}  // namespace

Mesh load_ply(const std::filesystem::path& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail("{}: mesh file '{}' not found", what, path.string());
  const std::string bytes = read_text_file(path);
  const std::string where = what + ": " + path.string();
  const auto end = bytes.find("end_header");
  if (bytes.rfind("ply", 0) != 0 || end == std::string::npos) fail("{}: not a PLY file", where);
  std::istringstream header(bytes.substr(0, end));
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::string line;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      std::string f;
      words >> f;
      if (f == "ascii") format = Format::ascii;
      else if (f == "binary_little_endian") format = Format::binary_le;
      else if (f == "binary_big_endian") format = Format::binary_be;
      else fail("{}: unknown PLY format '{}'", where, f);
    } else if (word == "element") {
      Element e;
      words >> e.name >> e.count;
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) fail("{}: PLY property before any element", where);
      Property p;
      words >> p.type;
      if (p.type == "list") words >> p.count_type >> p.type;
      words >> p.name;
      if (type_size(p.type) == 0 || (!p.count_type.empty() && type_size(p.count_type) == 0))
        fail("{}: unknown PLY property type in '{}'", where, line);
      elements.back().properties.push_back(p);
    }
  }
  std::size_t data = bytes.find('\n', end);
  data = data == std::string::npos ? bytes.size() : data + 1;
  Reader reader(bytes, data, format, where);
  Mesh m;
  for (const Element& e : elements) {
    for (std::size_t i = 0; i < e.count; ++i) {
      Vec3 p;
      for (const Property& prop : e.properties) {
        if (prop.count_type.empty()) {
          const double v = reader.read(prop.type);
          if (e.name == "vertex" && prop.name == "x") p.x = v;
          if (e.name == "vertex" && prop.name == "y") p.y = v;
          if (e.name == "vertex" && prop.name == "z") p.z = v;
          continue;
        }
        const auto n = static_cast<std::size_t>(reader.read(prop.count_type));
        std::vector<std::uint32_t> idx(n);
        for (auto& k : idx) {
          const double v = reader.read(prop.type);
          if (v < 0) fail("{}: negative vertex index", where);
          k = static_cast<std::uint32_t>(v);
        }
        if (e.name == "face" && (prop.name == "vertex_indices" || prop.name == "vertex_index"))
          for (std::size_t k = 1; k + 1 < n; ++k) m.triangles.push_back({idx[0], idx[k], idx[k + 1]});
      }
      if (e.name == "vertex") m.positions.push_back(p);
    }
  }
  for (const auto& t : m.triangles)
    for (auto k : t)
      if (k >= m.positions.size()) fail("{}: a face refers to vertex {} of {}", where, k, m.positions.size());
  if (m.triangles.empty()) fail("{}: no faces", where);
  return m;
}

}  // namespace bouguer
