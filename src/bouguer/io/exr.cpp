#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <optional>
#include <string>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/io/csv.h"
#include "bouguer/io/limits.h"
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

std::size_t pixel_type_bytes(Imf::PixelType t) { return t == Imf::HALF ? 2 : 4; }

// Checks the header against the limits and the bytes the file holds before anything is
// allocated for its pixels (docs/limits.md). `read` are the channels that will be decoded.
void check_exr_size(const Imf::Header& header, const std::vector<std::string>& read, std::uintmax_t file_bytes,
                    const std::string& name) {
  const Imath::Box2i dw = header.dataWindow();
  const std::int64_t width = std::int64_t{dw.max.x} - dw.min.x + 1, height = std::int64_t{dw.max.y} - dw.min.y + 1;
  if (width < 1 || height < 1 || width > kMaxImageDimension || height > kMaxImageDimension ||
      static_cast<std::uint64_t>(width * height) > kMaxImagePixels)
    fail("{}: EXR size {} × {} is outside 1 × 1 .. {} × {} pixels and {} pixels in all (docs/limits.md)", name, width,
         height, kMaxImageDimension, kMaxImageDimension, kMaxImagePixels);
  const auto pixels = static_cast<std::uint64_t>(width * height);
  if (pixels * read.size() > kMaxImageValues)
    fail("{}: EXR holds {} channels of {} pixels, more than the {} values an image may have (docs/limits.md)", name,
         read.size(), pixels, kMaxImageValues);
  double stored = 0.0;  // bytes of the channels read, as the file stores them before compression
  for (const std::string& c : read) {
    const Imf::Channel& ch = header.channels()[c];
    if (ch.xSampling != 1 || ch.ySampling != 1)
      fail("{}: EXR channel '{}' is subsampled ({} × {}); only full-resolution channels can be read", name,
           excerpt(c), ch.xSampling, ch.ySampling);
    stored += static_cast<double>(pixels * pixel_type_bytes(ch.type));
  }
  const double expansion = header.compression() == Imf::NO_COMPRESSION ? 1.0 : kMaxExrExpansion;
  if (stored > static_cast<double>(file_bytes) * expansion)
    fail("{}: EXR header claims {} × {} pixels in {} channels, more than its {} bytes can hold", name, width, height,
         read.size(), file_bytes);
}

}  // namespace

Film read_exr(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::uintmax_t file_bytes = require_regular_file(path, kMaxImageFileBytes);
  try {
    // OpenEXR's own sanity check then refuses larger data windows and tiles while it opens the file.
    Imf::Header::setMaxImageSize(kMaxImageDimension, kMaxImageDimension);
    Imf::Header::setMaxTileSize(kMaxImageDimension, kMaxImageDimension);
    Imf::InputFile file(path.c_str());
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
    check_exr_size(file.header(), read, file_bytes, name);
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
