#include "bouguer/spectra/cie.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <mutex>

#include <fmt/ranges.h>

#include "bouguer/core/error.h"
#include "bouguer/core/csv.h"
#include "bouguer/spectra/spectrum_csv.h"

namespace bouguer::data {
// Embedded from data/cie by cmake/EmbedData.cmake.
extern const std::string_view cmf_1931_2deg, cmf_1964_10deg, illuminant_d65, illuminant_d50, illuminant_a,
    illuminant_f2, illuminant_f7, illuminant_f11;
}  // namespace bouguer::data

namespace bouguer {
namespace {

ObserverTable load_observer(std::string_view text, const std::string& name) {
  const CsvTable table = parse_csv(text, name);
  ObserverTable t;
  for (std::size_t column = 1; column <= 3; ++column) {
    const TabulatedSpectrum s = spectrum_from_csv(table, column);
    auto& out = column == 1 ? t.xbar : (column == 2 ? t.ybar : t.zbar);
    for (int i = 0; i < kCmfCount; ++i) out.push_back(eval(s, kLambdaMinNm + i));
  }
  for (double y : t.ybar) t.ybar_sum += y;
  return t;
}

std::string lower(std::string_view s) {
  std::string r(s);
  std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return r;
}

const TabulatedSpectrum& cie_table(std::string_view text, const char* name) {
  // Parsed once per process; the tables are immutable afterwards.
  // std::map keeps references stable as entries are added.
  static std::map<std::string, TabulatedSpectrum, std::less<>> cache;
  static std::mutex lock;
  std::lock_guard guard(lock);
  if (const auto it = cache.find(name); it != cache.end()) return it->second;
  return cache.emplace(name, spectrum_from_csv(parse_csv(text, name), 1)).first->second;
}

std::optional<double> parse_blackbody_kelvin(std::string_view name) {
  constexpr std::string_view prefix = "blackbody:";
  if (name.substr(0, prefix.size()) != prefix) return std::nullopt;
  std::string_view rest = name.substr(prefix.size());
  if (!rest.empty() && (rest.back() == 'k')) rest.remove_suffix(1);
  double kelvin = 0.0;
  const auto [ptr, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), kelvin);
  if (ec != std::errc() || ptr != rest.data() + rest.size() || !(kelvin >= 100.0 && kelvin <= 1e6)) return std::nullopt;
  return kelvin;
}

}  // namespace

std::string_view observer_name(Observer o) {
  return o == Observer::cie1931_2deg ? "CIE 1931 2°" : "CIE 1964 10°";
}

const ObserverTable& observer_table(Observer o) {
  static const ObserverTable t1931 = load_observer(data::cmf_1931_2deg, "data/cie/cmf_1931_2deg.csv");
  static const ObserverTable t1964 = load_observer(data::cmf_1964_10deg, "data/cie/cmf_1964_10deg.csv");
  return o == Observer::cie1931_2deg ? t1931 : t1964;
}

Vec3 spectrum_to_xyz(const Spectrum& s, Observer o) {
  const ObserverTable& t = observer_table(o);
  Vec3 xyz;
  for (int i = 0; i < kCmfCount; ++i) {
    const double v = eval(s, kLambdaMinNm + i);
    xyz += Vec3{t.xbar[i], t.ybar[i], t.zbar[i]} * v;
  }
  return xyz / t.ybar_sum;
}

double luminance(const Spectrum& s) { return spectrum_to_xyz(s, Observer::cie1931_2deg).y; }

Spectrum normalised_to_luminance(const Spectrum& s, double luminance_y) {
  const double y = luminance(s);
  if (!(y > 0.0)) fail("cannot normalise a spectrum with zero luminance");
  return scaled(s, luminance_y / y);
}

std::optional<Spectrum> named_illuminant_spd(std::string_view name) {
  const std::string n = lower(name);
  if (n == "e") return ConstantSpectrum{1.0};
  if (n == "d65") return cie_table(data::illuminant_d65, "D65");
  if (n == "d50") return cie_table(data::illuminant_d50, "D50");
  if (n == "a") return cie_table(data::illuminant_a, "A");
  if (n == "f2") return cie_table(data::illuminant_f2, "F2");
  if (n == "f7") return cie_table(data::illuminant_f7, "F7");
  if (n == "f11") return cie_table(data::illuminant_f11, "F11");
  if (const auto kelvin = parse_blackbody_kelvin(n)) return BlackbodySpectrum{*kelvin, 1.0};
  return std::nullopt;
}

std::vector<std::string> illuminant_names() { return {"D65", "D50", "A", "E", "F2", "F7", "F11", "blackbody:<kelvin>"}; }

Spectrum named_illuminant(std::string_view name, double scale) {
  const auto spd = named_illuminant_spd(name);
  if (!spd) fail("unknown illuminant '{}' (known: {})", name, fmt::join(illuminant_names(), ", "));
  return normalised_to_luminance(*spd, scale);
}

Vec3 xy_to_xyz(double x, double y, double luminance_y) {
  return {x * luminance_y / y, luminance_y, (1.0 - x - y) * luminance_y / y};
}

}  // namespace bouguer
