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

Film read_exr(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail("{}: file not found", path.string());
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int width = dw.max.x - dw.min.x + 1, height = dw.max.y - dw.min.y + 1;
    const Imf::ChannelList& channels = file.header().channels();
    for (const char* c : {"R", "G", "B"})
      if (!channels.findChannel(c)) fail("{}: EXR has no '{}' channel", path.string(), c);
    std::vector<std::pair<double, std::string>> spectral;
    for (auto it = channels.begin(); it != channels.end(); ++it)
      if (const auto nm = parse_spectral_channel(it.name())) spectral.emplace_back(*nm, it.name());
    std::sort(spectral.begin(), spectral.end());
    std::vector<double> wavelengths(spectral.size());
    std::transform(spectral.begin(), spectral.end(), wavelengths.begin(), [](const auto& p) { return p.first; });
    Film film(width, height, std::move(wavelengths));

    // Slices address pixel (x, y) of the data window at base + x·xs + y·ys, so shift the base.
    const std::ptrdiff_t origin = static_cast<std::ptrdiff_t>(dw.min.x) + static_cast<std::ptrdiff_t>(dw.min.y) * width;
    Imf::FrameBuffer fb;
    char* rgb_base = reinterpret_cast<char*>(film.rgb.data() - 3 * origin);
    const std::size_t xs = 3 * kFloat, ys = xs * width;
    fb.insert("R", Imf::Slice(Imf::FLOAT, rgb_base, xs, ys));
    fb.insert("G", Imf::Slice(Imf::FLOAT, rgb_base + kFloat, xs, ys));
    fb.insert("B", Imf::Slice(Imf::FLOAT, rgb_base + 2 * kFloat, xs, ys));
    const std::size_t n = spectral.size();
    char* spectral_base = reinterpret_cast<char*>(film.spectral.data() - static_cast<std::ptrdiff_t>(n) * origin);
    for (std::size_t i = 0; i < n; ++i)
      fb.insert(spectral[i].second, Imf::Slice(Imf::FLOAT, spectral_base + i * kFloat, n * kFloat, n * kFloat * width));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    // A Film is linear Rec.709 (D65); RGB in other primaries (ACEScg, Rec.2020, ...) is converted,
    // adapting a non-D65 white with Bradford as colour-managed pipelines do.
    if (const auto cs = exr_color_space(file.header())) {
      const auto column = [&](Vec3 e) { return xyz_to_linear_rgb(kRec709, linear_rgb_to_xyz(*cs, e)); };
      const Mat3 to_709 = Mat3::from_columns(column({1, 0, 0}), column({0, 1, 0}), column({0, 0, 1}));
      for (std::size_t i = 0; i < film.rgb.size(); i += 3) {
        const Vec3 rgb = to_709 * Vec3{film.rgb[i], film.rgb[i + 1], film.rgb[i + 2]};
        film.rgb[i] = static_cast<float>(rgb.x);
        film.rgb[i + 1] = static_cast<float>(rgb.y);
        film.rgb[i + 2] = static_cast<float>(rgb.z);
      }
    }
    return film;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail("{}: cannot read EXR: {}", path.string(), e.what());
  }
}

}  // namespace bouguer
