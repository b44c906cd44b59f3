#include <OpenEXR/Iex.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <optional>
#include <string>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/core/csv.h"
#include "bouguer/core/limits.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/io/image_io.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

constexpr std::size_t kFloat = sizeof(float);

// The colour space an EXR's chromaticities attribute names. Coordinates within 1e-4 of Rec.709/D65
// (floats in the file) count as Rec.709, so our own files and the common case stay bit-exact.
std::optional<ColorSpace> exr_color_space(const Imf::Header& header) {
  if (!Imf::hasChromaticities(header)) return std::nullopt;
  const Imf::Chromaticities& c = Imf::chromaticities(header);
  const auto xy = [](const Imath::V2f& v) { return Chromaticity{v.x, v.y}; };
  const auto near = [](Chromaticity a, Chromaticity b) {
    return std::abs(a.x - b.x) < 1e-4 && std::abs(a.y - b.y) < 1e-4;
  };
  ColorSpace cs{"EXR chromaticities", xy(c.red), xy(c.green), xy(c.blue), xy(c.white)};
  if (near(cs.white, kD65White)) cs.white = kD65White;  // exactly D65: no Bradford step for float rounding
  const bool rec709 = near(cs.red, kRec709.red) && near(cs.green, kRec709.green) && near(cs.blue, kRec709.blue) &&
                      near(cs.white, kD65White);
  if (rec709) return std::nullopt;
  return cs;
}

Imf::Header make_rgb_header(const Film& film) {
  Imf::Header header(film.width, film.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::addChromaticities(header, Imf::Chromaticities());  // defaults: Rec.709 primaries, D65 white
  for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
  return header;
}

void insert_rgb_slices(Imf::FrameBuffer& fb, const Film& film) {
  auto* base = reinterpret_cast<char*>(const_cast<float*>(film.rgb.data()));
  const std::size_t x_stride = 3 * kFloat, y_stride = x_stride * film.width;
  fb.insert("R", Imf::Slice(Imf::FLOAT, base, x_stride, y_stride));
  fb.insert("G", Imf::Slice(Imf::FLOAT, base + kFloat, x_stride, y_stride));
  fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * kFloat, x_stride, y_stride));
}

void write_with_header(const std::filesystem::path& path, const Imf::Header& header, const Imf::FrameBuffer& fb,
                       int height) {
  write_atomically(path, [&](const std::filesystem::path& temp) {
    try {
      Imf::OutputFile file(temp.c_str(), header);
      file.setFrameBuffer(fb);
      file.writePixels(height);
    } catch (const std::exception& e) {
      fail("{}: EXR write failed: {}", path.string(), e.what());
    }
  });
}

// "S0.550,000000nm" -> 550; nullopt for other channel names (polarised S1..S3 are not read).
std::optional<double> parse_spectral_channel(const std::string& name) {
  if (name.size() < 6 || name.rfind("S0.", 0) != 0 || name.substr(name.size() - 2) != "nm") return std::nullopt;
  std::string number = name.substr(3, name.size() - 5);
  std::replace(number.begin(), number.end(), ',', '.');
  char* end = nullptr;
  const double nm = std::strtod(number.c_str(), &end);
  if (end != number.c_str() + number.size() || !(nm > 0.0)) return std::nullopt;
  return nm;
}

}  // namespace

std::string spectral_channel_name(double wavelength_nm) {
  std::string number = fmt::format("{:.6f}", wavelength_nm);
  std::replace(number.begin(), number.end(), '.', ',');
  return "S0." + number + "nm";
}

void write_exr(const std::filesystem::path& path, const Film& film) {
  const Imf::Header header = make_rgb_header(film);
  Imf::FrameBuffer fb;
  insert_rgb_slices(fb, film);
  write_with_header(path, header, fb, film.height);
}

void write_spectral_exr(const std::filesystem::path& path, const Film& film) {
  if (!film.has_spectra()) fail("{}: cannot write a spectral EXR: the render kept no spectra", path.string());
  Imf::Header header = make_rgb_header(film);
  header.insert("spectralLayoutVersion", Imf::StringAttribute("1.0"));
  header.insert("emissiveUnits", Imf::StringAttribute("W.m^-2.sr^-1"));
  header.insert("bouguerRadianceScale",
                Imf::StringAttribute("relative: a named illuminant with scale 1 has luminance Y = 1 (CIE 1931)"));
  const std::size_t n = film.wavelengths_nm.size();
  Imf::FrameBuffer fb;
  insert_rgb_slices(fb, film);
  auto* base = reinterpret_cast<char*>(const_cast<float*>(film.spectral.data()));
  for (std::size_t i = 0; i < n; ++i) {
    const std::string name = spectral_channel_name(film.wavelengths_nm[i]);
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    fb.insert(name, Imf::Slice(Imf::FLOAT, base + i * kFloat, n * kFloat, n * kFloat * film.width));
  }
  write_with_header(path, header, fb, film.height);
}

namespace {

// The matrix from the file's RGB to linear Rec.709. Chromaticities that describe no colour space
// (collinear primaries, a white at y = 0, numbers far outside the diagram) are an Error.
Mat3 to_rec709(const ColorSpace& cs, const std::string& name) {
  const auto plausible = [](Chromaticity c, double min_y) {
    return std::isfinite(c.x) && std::isfinite(c.y) && std::abs(c.x) <= 2.0 && std::abs(c.y) <= 2.0 &&
           std::abs(c.y) >= min_y;
  };
  const double area = (cs.green.x - cs.red.x) * (cs.blue.y - cs.red.y) - (cs.blue.x - cs.red.x) * (cs.green.y - cs.red.y);
  if (!plausible(cs.red, 1e-6) || !plausible(cs.green, 1e-6) || !plausible(cs.blue, 1e-6) ||
      !plausible(cs.white, 1e-3) || cs.white.y < 0.0 || !(std::abs(area) > 1e-6))
    fail("{}: the EXR chromaticities attribute describes no usable colour space", name);
  const auto column = [&](Vec3 e) { return xyz_to_linear_rgb(kRec709, linear_rgb_to_xyz(cs, e)); };
  const Mat3 m = Mat3::from_columns(column({1, 0, 0}), column({0, 1, 0}), column({0, 0, 1}));
  for (const auto& row : m.m)
    for (const double v : row)
      if (!(std::abs(v) <= 1e3)) fail("{}: the EXR chromaticities attribute describes no usable colour space", name);
  return m;
}

// ---- What OpenEXR would allocate, checked before it does ----------------------------------
// OpenEXR sizes its buffers from the header as it opens a file: an attribute's stated size, the
// chunk offset table, line and tile buffers. The header is therefore scanned here first, and
// every such size checked against the limits and the bytes the file holds (docs/limits.md).

struct ExrChannel {
  std::string name;
  std::int32_t type = 0;  // 0 UINT, 1 HALF, 2 FLOAT
  std::int32_t x_sampling = 1, y_sampling = 1;
};

struct ExrLayout {
  std::optional<Imath::Box2i> data_window;
  std::vector<ExrChannel> channels;
  int compression = Imf::NO_COMPRESSION;
  std::optional<Imf::TileDescription> tiles;
  std::optional<std::int64_t> chunk_count;
};

// Lines per chunk of a scan-line file; 0 for an unknown compression.
int lines_per_chunk(int compression) {
  switch (compression) {
    case Imf::NO_COMPRESSION: case Imf::RLE_COMPRESSION: case Imf::ZIPS_COMPRESSION: return 1;
    case Imf::ZIP_COMPRESSION: case Imf::PXR24_COMPRESSION: return 16;
    case Imf::PIZ_COMPRESSION: case Imf::B44_COMPRESSION: case Imf::B44A_COMPRESSION: case Imf::DWAA_COMPRESSION:
      return 32;
    case Imf::DWAB_COMPRESSION: return 256;
    default: return 0;
  }
}

void check_exr_layout(const ExrLayout& l, std::uintmax_t file_bytes, const std::string& name) {
  if (!l.data_window) fail("{}: the EXR header has no dataWindow", name);
  const Imath::Box2i& dw = *l.data_window;
  const std::int64_t width = std::int64_t{dw.max.x} - dw.min.x + 1, height = std::int64_t{dw.max.y} - dw.min.y + 1;
  if (width < 1 || height < 1 || width > kMaxImageDimension || height > kMaxImageDimension ||
      static_cast<std::uint64_t>(width * height) > kMaxImagePixels)
    fail("{}: EXR size {} × {} is outside 1 × 1 .. {} × {} pixels and {} pixels in all (docs/limits.md)", name, width,
         height, kMaxImageDimension, kMaxImageDimension, kMaxImagePixels);
  double bytes_per_pixel = 0.0, stored = 0.0;  // of all channels, as the file stores them uncompressed
  for (const ExrChannel& c : l.channels) {
    if (c.type < 0 || c.type > 2 || c.x_sampling < 1 || c.y_sampling < 1 || c.x_sampling > width ||
        c.y_sampling > height)
      fail("{}: EXR channel '{}' has an unknown type or sampling", name, excerpt(c.name));
    const double size = c.type == Imf::HALF ? 2.0 : 4.0;
    bytes_per_pixel += size;
    stored += size * static_cast<double>((width + c.x_sampling - 1) / c.x_sampling) *
              static_cast<double>((height + c.y_sampling - 1) / c.y_sampling);
  }
  const int lines = lines_per_chunk(l.compression);
  if (lines == 0) fail("{}: unknown EXR compression {}", name, l.compression);
  const double file = static_cast<double>(file_bytes);
  const double expansion = l.compression == Imf::NO_COMPRESSION ? 1.0 : kMaxExrExpansion;
  if (stored > file * expansion)
    fail("{}: EXR header claims {} × {} pixels in {} channels, more than its {} bytes can hold", name, width, height,
         l.channels.size(), file_bytes);
  // One chunk's buffer, and the offset table (8 bytes a chunk, level 0 of a tiled file).
  double buffer = 0.0, chunks = 0.0;
  if (l.tiles) {
    const double tx = l.tiles->xSize, ty = l.tiles->ySize;
    if (!(tx >= 1 && ty >= 1 && tx <= kMaxImageDimension && ty <= kMaxImageDimension))
      fail("{}: EXR tiles of {} × {} pixels are outside 1 .. {}", name, tx, ty, kMaxImageDimension);
    buffer = tx * ty * bytes_per_pixel;
    chunks = std::ceil(static_cast<double>(width) / tx) * std::ceil(static_cast<double>(height) / ty);
  } else {
    buffer = static_cast<double>(width) * bytes_per_pixel * lines;
    chunks = std::ceil(static_cast<double>(height) / lines);
  }
  if (l.chunk_count) chunks = std::max(chunks, static_cast<double>(*l.chunk_count));
  if (buffer > file * kMaxExrExpansion || chunks * 8.0 > file || (l.chunk_count && *l.chunk_count < 0))
    fail("{}: EXR header claims {} × {} pixels in chunks that its {} bytes cannot hold", name, width, height,
         file_bytes);
}

std::int32_t le_i32(std::string_view v, std::size_t at) {
  std::uint32_t u = 0;
  for (int k = 3; k >= 0; --k) u = (u << 8) | static_cast<unsigned char>(v[at + static_cast<std::size_t>(k)]);
  return static_cast<std::int32_t>(u);
}

// A chlist value: per channel its name, type, pLinear, 3 reserved bytes, x and y sampling; an
// empty name ends it, exactly at the end of the value. nullopt when it does not.
std::optional<std::vector<ExrChannel>> parse_chlist(std::string_view v) {
  std::vector<ExrChannel> channels;
  for (std::size_t at = 0; at < v.size();) {
    if (v[at] == '\0') return at + 1 == v.size() ? std::optional(channels) : std::nullopt;
    const std::size_t end = v.find('\0', at);
    if (end == std::string_view::npos || end - at > 255 || v.size() - end - 1 < 16) return std::nullopt;
    channels.push_back({std::string(v.substr(at, end - at)), le_i32(v, end + 1), le_i32(v, end + 9), le_i32(v, end + 13)});
    at = end + 17;
  }
  return std::nullopt;
}

// OpenEXR reads a value of a type it knows by the type's own layout, not by the stated size; both
// must agree, or its reading and this scan would part ways (and it would take later bytes for the
// next attribute's size). Unknown types and strings are read by their stated size.
bool value_fills_its_size(std::string_view type, std::string_view v) {
  static constexpr std::pair<std::string_view, std::size_t> kFixed[] = {
      {"box2f", 16},   {"box2i", 16},  {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1},
      {"double", 8},   {"envmap", 1},  {"float", 4},           {"int", 4},         {"keycode", 28},
      {"lineOrder", 1}, {"m33d", 72},  {"m33f", 36},           {"m44d", 128},      {"m44f", 64},
      {"rational", 8}, {"tiledesc", 9}, {"timecode", 8},       {"v2d", 16},        {"v2f", 8},
      {"v2i", 8},      {"v3d", 24},    {"v3f", 12},            {"v3i", 12}};
  for (const auto& [t, n] : kFixed)
    if (type == t) return v.size() == n;
  if (type == "chlist") return parse_chlist(v).has_value();
  if (type == "floatvector") return v.size() % 4 == 0;
  if (type == "idmanifest") return v.size() >= 4;
  if (type == "preview") {
    if (v.size() < 8) return false;
    const std::int32_t w = le_i32(v, 0), h = le_i32(v, 4);  // 4 bytes (RGBA) a pixel
    return w >= 0 && h >= 0 && (v.size() - 8) % 4 == 0 &&
           static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) == (v.size() - 8) / 4;
  }
  if (type == "stringvector") {
    std::size_t at = 0;
    while (at < v.size()) {
      if (v.size() - at < 4) return false;
      const std::int32_t n = le_i32(v, at);
      at += 4;
      if (n < 0 || static_cast<std::size_t>(n) > v.size() - at) return false;
      at += static_cast<std::size_t>(n);
    }
  }
  return true;
}

// The header(s) of an EXR file as bytes: magic, version, then per part attributes (name, type
// name, size, value) up to an empty name; multi-part files end the list of headers with another.
std::vector<ExrLayout> scan_exr_headers(std::string_view bytes, const std::string& name) {
  std::size_t pos = 0;
  const auto need = [&](std::size_t n) {
    if (bytes.size() - pos < n) fail("{}: the EXR header ends early", name);
  };
  const auto word = [&](std::size_t max_length) {
    const std::size_t end = bytes.find('\0', pos);
    if (end == std::string_view::npos || end - pos > max_length) fail("{}: the EXR header holds a bad name", name);
    const std::string_view w = bytes.substr(pos, end - pos);
    pos = end + 1;
    return w;
  };
  need(8);
  if (bytes.substr(0, 4) != std::string_view("\x76\x2f\x31\x01", 4)) fail("{}: not an OpenEXR file", name);
  const auto version = static_cast<std::uint32_t>(le_i32(bytes, 4));
  if ((version & 0xffu) != 2) fail("{}: unsupported OpenEXR version {}", name, version & 0xffu);
  const bool long_names = version & 0x400u, multipart = version & 0x1000u, tiled = version & 0x200u;
  pos = 8;
  std::vector<ExrLayout> parts;
  while (true) {
    ExrLayout l;
    bool tiled_part = tiled;
    while (true) {
      need(1);
      if (bytes[pos] == '\0') {
        ++pos;
        break;
      }
      const std::string_view attribute = word(long_names ? 255 : 31), type = word(long_names ? 255 : 31);
      need(4);
      const std::int32_t size = le_i32(bytes, pos);
      pos += 4;
      if (size < 0 || static_cast<std::size_t>(size) > bytes.size() - pos)
        fail("{}: EXR attribute '{}' claims {} bytes, but only {} follow", name, excerpt(attribute), size,
             bytes.size() - pos);
      const std::string_view v = bytes.substr(pos, static_cast<std::size_t>(size));
      pos += v.size();
      if (!value_fills_its_size(type, v))
        fail("{}: EXR attribute '{}' of type '{}' does not fill its {} bytes", name, excerpt(attribute), excerpt(type),
             size);
      if (attribute == "dataWindow" && type == "box2i") {
        l.data_window = Imath::Box2i({le_i32(v, 0), le_i32(v, 4)}, {le_i32(v, 8), le_i32(v, 12)});
      } else if (attribute == "compression" && type == "compression") {
        l.compression = static_cast<unsigned char>(v[0]);
      } else if (attribute == "tiles" && type == "tiledesc") {
        l.tiles = Imf::TileDescription(static_cast<std::uint32_t>(le_i32(v, 0)), static_cast<std::uint32_t>(le_i32(v, 4)));
      } else if (attribute == "chunkCount" && type == "int") {
        l.chunk_count = le_i32(v, 0);
      } else if (attribute == "type" && type == "string") {
        tiled_part = v == "tiledimage" || v == "deeptile";
      } else if (attribute == "channels" && type == "chlist") {
        l.channels = *parse_chlist(v);
      }
    }
    if (!tiled_part) l.tiles.reset();
    parts.push_back(std::move(l));
    if (!multipart) return parts;
    need(1);
    if (bytes[pos] == '\0') return parts;
  }
}

// The file's bytes as OpenEXR's input: reads never pass the end.
class MemoryStream : public Imf::IStream {
 public:
  MemoryStream(std::string& bytes, const std::string& name) : Imf::IStream(name.c_str()), bytes_(bytes) {}
  bool isMemoryMapped() const override { return true; }
  char* readMemoryMapped(int n) override {
    require(n);
    char* p = bytes_.data() + pos_;
    pos_ += static_cast<std::size_t>(n);
    return p;
  }
  bool read(char c[], int n) override {
    std::memcpy(c, readMemoryMapped(n), static_cast<std::size_t>(n));
    return pos_ < bytes_.size();
  }
  std::uint64_t tellg() override { return pos_; }
  void seekg(std::uint64_t pos) override { pos_ = static_cast<std::size_t>(std::min<std::uint64_t>(pos, bytes_.size())); }

 private:
  void require(int n) const {
    if (n < 0 || bytes_.size() - pos_ < static_cast<std::size_t>(n)) throw Iex::InputExc("unexpected end of file");
  }
  std::string& bytes_;
  std::size_t pos_ = 0;
};

ExrLayout layout_of(const Imf::Header& header) {
  ExrLayout l{header.dataWindow(), {}, header.compression(), std::nullopt, std::nullopt};
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
    l.channels.push_back({it.name(), it.channel().type, it.channel().xSampling, it.channel().ySampling});
  if (header.hasTileDescription()) l.tiles = header.tileDescription();
  if (header.hasChunkCount()) l.chunk_count = header.chunkCount();
  return l;
}

}  // namespace

void check_exr_before_opening(std::string_view bytes, const std::string& name) {
  for (const ExrLayout& part : scan_exr_headers(bytes, name)) check_exr_layout(part, bytes.size(), name);
}

Film read_exr(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::string bytes = read_file_bytes(path, kMaxImageFileBytes);
  for (const ExrLayout& part : scan_exr_headers(bytes, name)) check_exr_layout(part, bytes.size(), name);
  try {
    // OpenEXR's own sanity check refuses larger data windows and tiles too.
    Imf::Header::setMaxImageSize(kMaxImageDimension, kMaxImageDimension);
    Imf::Header::setMaxTileSize(kMaxImageDimension, kMaxImageDimension);
    MemoryStream stream(bytes, name);
    Imf::InputFile file(stream);
    const Imath::Box2i dw = file.header().dataWindow();
    const Imf::ChannelList& channels = file.header().channels();
    for (const char* c : {"R", "G", "B"})
      if (!channels.findChannel(c)) fail("{}: EXR has no '{}' channel", name, c);
    std::vector<std::pair<double, std::string>> spectral;
    for (auto it = channels.begin(); it != channels.end(); ++it)
      if (const auto nm = parse_spectral_channel(it.name())) {
        if (!(*nm >= kMinWavelengthNm && *nm <= kMaxWavelengthNm))
          fail("{}: spectral channel '{}' is outside {} .. {} nm", name, excerpt(it.name()), kMinWavelengthNm,
               kMaxWavelengthNm);
        spectral.emplace_back(*nm, it.name());
      }
    std::sort(spectral.begin(), spectral.end());
    for (std::size_t i = 1; i < spectral.size(); ++i)
      if (spectral[i].first == spectral[i - 1].first)
        fail("{}: spectral channels '{}' and '{}' name the same wavelength", name, excerpt(spectral[i - 1].second),
             excerpt(spectral[i].second));
    std::vector<std::string> read = {"R", "G", "B"};
    for (const auto& p : spectral) read.push_back(p.second);
    // Again on the header as OpenEXR read it; then what the Film will hold.
    check_exr_layout(layout_of(file.header()), bytes.size(), name);
    const std::size_t pixels = static_cast<std::size_t>(dw.max.x - dw.min.x + 1) * (dw.max.y - dw.min.y + 1);
    if (pixels * read.size() > kMaxImageValues)
      fail("{}: EXR holds {} channels of {} pixels, more than the {} values an image may have (docs/limits.md)", name,
           read.size(), pixels, kMaxImageValues);
    for (const std::string& c : read) {
      const Imf::Channel& ch = channels[c];
      if (ch.xSampling != 1 || ch.ySampling != 1)
        fail("{}: EXR channel '{}' is subsampled ({} × {}); only full-resolution channels can be read", name,
             excerpt(c), ch.xSampling, ch.ySampling);
    }
    const int width = dw.max.x - dw.min.x + 1, height = dw.max.y - dw.min.y + 1;
    std::vector<double> wavelengths(spectral.size());
    std::transform(spectral.begin(), spectral.end(), wavelengths.begin(), [](const auto& p) { return p.first; });
    Film film(width, height, std::move(wavelengths));

    // Slices address pixel (x, y) of the data window; Slice::Make shifts the base by its origin.
    Imf::FrameBuffer fb;
    const std::size_t xs = 3 * kFloat, ys = xs * width;
    for (int c = 0; c < 3; ++c)
      fb.insert(read[c], Imf::Slice::Make(Imf::FLOAT, film.rgb.data() + c, dw, xs, ys));
    const std::size_t n = spectral.size();
    for (std::size_t i = 0; i < n; ++i)
      fb.insert(spectral[i].second,
                Imf::Slice::Make(Imf::FLOAT, film.spectral.data() + i, dw, n * kFloat, n * kFloat * width));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    const auto require_finite = [&](const char* after) {
      for (std::size_t i = 0; i < film.rgb.size(); ++i)
        if (!std::isfinite(film.rgb[i]))
          fail("{}: pixel ({}, {}) channel {} is {}{}, not a finite number", name, i / 3 % width, i / 3 / width,
               read[i % 3], static_cast<double>(film.rgb[i]), after);
    };
    require_finite("");
    for (std::size_t i = 0; i < film.spectral.size(); ++i)
      if (!std::isfinite(film.spectral[i]))
        fail("{}: pixel ({}, {}) channel '{}' is {}, not a finite number", name, i / n % width, i / n / width,
             excerpt(spectral[i % n].second), static_cast<double>(film.spectral[i]));
    // A Film is linear Rec.709 (D65); RGB in other primaries (ACEScg, Rec.2020, ...) is converted,
    // adapting a non-D65 white with Bradford as colour-managed pipelines do.
    if (const auto cs = exr_color_space(file.header())) {
      const Mat3 to_709 = to_rec709(*cs, name);
      for (std::size_t i = 0; i < film.rgb.size(); i += 3) {
        const Vec3 rgb = to_709 * Vec3{film.rgb[i], film.rgb[i + 1], film.rgb[i + 2]};
        film.rgb[i] = static_cast<float>(rgb.x);
        film.rgb[i + 1] = static_cast<float>(rgb.y);
        film.rgb[i + 2] = static_cast<float>(rgb.z);
      }
      require_finite(" after conversion to Rec.709");
    }
    return film;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail("{}: cannot read EXR: {}", name, excerpt(e.what(), 200));
  }
}

}  // namespace bouguer
