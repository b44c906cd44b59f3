#include "bouguer/media/scattering_library.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <charconv>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "bouguer/core/error.h"
#include "bouguer/media/milk.h"
#include "bouguer/spectra/rgb_to_spectrum.h"

namespace bouguer::data {
extern const std::string_view narasimhan2006;
}  // namespace bouguer::data

namespace bouguer {
namespace {

constexpr std::string_view kFrisvad =
    "J. R. Frisvad, N. J. Christensen and H. W. Jensen, 'Computing the scattering properties of participating "
    "media using Lorenz-Mie theory', ACM Trans. Graph. 26(3), article 60 (SIGGRAPH 2007); "
    "inputs: Hale & Querry 1973 (water), Michalski et al. 2001 (fat), Du et al. "
    "1998 (riboflavin), Walstra (fat globule sizes)";
constexpr std::string_view kNarasimhan =
    "S. G. Narasimhan, M. Gupta, C. Donner, R. Ramamoorthi, S. K. Nayar and H. W. Jensen, 'Acquiring scattering "
    "properties of participating media by dilution', ACM Trans. Graph. 25(3) (SIGGRAPH 2006), "
    "doi:10.1145/1141911.1141986, Table 1 (as transcribed by pbrt-v2 and CudaTracerLib; see "
    "data/scattering/narasimhan2006.csv)";

ScatteringLibraryEntry milk_entry(std::string name, std::string description, const MilkComposition& milk) {
  const MilkSpectra s = milk_spectra(milk);
  ScatteringLibraryEntry e;
  e.name = std::move(name);
  e.description = std::move(description);
  e.measured = fmt::format(
      "computed, not measured: Lorenz-Mie theory (media/mie.h) for log-normal fat globules (r_vs {:.3f} um) and "
      "casein micelles (r_vs 43 nm) in water with riboflavin, 360-830 nm in 10 nm steps (inputs tabulated "
      "375-775 nm, held beyond); the phase function's g is the sigma_s-weighted mean of g(lambda) over 360-830 nm; the index is the host's (water)",
      fat_globule_size(milk).r_vs_um);
  e.citation = std::string(kFrisvad);
  e.ior = milk_host_index(589.29);  // the model's: its host's index, at the sodium d line
  e.sigma_s_per_m = s.sigma_s_per_m;
  e.sigma_a_per_m = s.sigma_a_per_m;
  // The phase function holds one g for all wavelengths: the σ_s-weighted mean over the table.
  double sum = 0.0, weight = 0.0;
  for (std::size_t i = 0; i < s.g.value.size(); ++i) {
    sum += s.g.value[i] * s.sigma_s_per_m.value[i];
    weight += s.sigma_s_per_m.value[i];
  }
  e.phase = HenyeyGreensteinPhase{weight > 0.0 ? sum / weight : 0.0};
  return e;
}

// "Head & Shoulders Shampoo" -> "head_shoulders_shampoo".
std::string snake_case(std::string_view name) {
  std::string out;
  for (char c : name) {
    if (std::isalnum(static_cast<unsigned char>(c))) {
      out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    } else if (!out.empty() && out.back() != '_') {
      out.push_back('_');
    }
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out;
}

// RGB lifted as the scene loader lifts RGB scattering coefficients: a sigmoid spectrum around 1/2,
// scaled by 2·max.
Spectrum lift_rgb(const Vec3& rgb_per_m) {
  const double peak = std::max({rgb_per_m.x, rgb_per_m.y, rgb_per_m.z});
  if (!(peak > 0.0)) return ConstantSpectrum{0.0};
  return scaled(Spectrum{rgb_to_reflectance(rgb_per_m / (2.0 * peak))}, 2.0 * peak);
}

struct NarasimhanRow {
  std::string name;
  std::array<double, 9> v{};  // σ_t RGB, σ_s RGB (per mm), g RGB (NaN: none given)
};

double number(std::string_view cell, int line_no) {
  if (cell == "nan") return std::numeric_limits<double>::quiet_NaN();
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc{} || ptr != cell.data() + cell.size() || !std::isfinite(v) || v < 0.0)
    fail("data/scattering/narasimhan2006.csv, line {}: '{}' is not a non-negative number", line_no, cell);
  return v;
}

// The table's first column is a name, so it is read here rather than by parse_csv (numbers only).
std::vector<NarasimhanRow> parse_narasimhan(std::string_view text) {
  std::vector<NarasimhanRow> rows;
  bool header = true;
  int line_no = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    const std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    ++line_no;
    if (line.empty() || line.front() == '#') continue;
    if (std::exchange(header, false)) continue;
    std::vector<std::string_view> cells;
    for (std::size_t start = 0;;) {
      const std::size_t comma = line.find(',', start);
      cells.push_back(line.substr(start, comma - start));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (cells.size() != 10) fail("data/scattering/narasimhan2006.csv, line {}: expected 10 cells", line_no);
    NarasimhanRow r;
    r.name = std::string(cells[0]);
    for (std::size_t i = 0; i < 9; ++i) r.v[i] = number(cells[i + 1], line_no);
    rows.push_back(std::move(r));
  }
  return rows;
}

ScatteringLibraryEntry narasimhan_entry(const NarasimhanRow& r) {
  const Vec3 sigma_t{r.v[0], r.v[1], r.v[2]}, sigma_s{r.v[3], r.v[4], r.v[5]};
  double g_sum = 0.0;
  int g_count = 0;
  for (std::size_t i = 6; i < 9; ++i)
    if (std::isfinite(r.v[i])) g_sum += r.v[i], ++g_count;
  ScatteringLibraryEntry e;
  e.name = snake_case(r.name);
  e.description = fmt::format("{}, diluted in water as Narasimhan et al. measured it (the values hold at that "
                              "dilution, not for the neat medium)", r.name);
  e.measured = fmt::format(
      "RGB ONLY: sigma_t and sigma_s per colour channel of the authors' camera, fitted to one HDR photograph in the "
      "single-scattering regime, printed in 1e-2 per mm; sigma_a = sigma_t - sigma_s; spectra lifted from RGB as the scene "
      "loader lifts RGB coefficients; g = the mean of the {} channels' Henyey-Greenstein g",
      g_count == 3 ? "three" : (g_count == 2 ? "two scattering" : "one scattering"));
  e.citation = std::string(kNarasimhan);
  e.ior = 1.333;  // diluted in water
  // The table's unit is 10⁻² per mm (data/scattering/narasimhan2006.csv): 10 per metre.
  e.sigma_s_per_m = lift_rgb(sigma_s * 10.0);
  e.sigma_a_per_m = lift_rgb((sigma_t - sigma_s) * 10.0);
  e.phase = HenyeyGreensteinPhase{g_count > 0 ? g_sum / g_count : 0.0};
  e.rgb_measured = true;
  return e;
}

std::vector<ScatteringLibraryEntry> load_entries() {
  std::vector<ScatteringLibraryEntry> out;
  // Whole and skimmed milk as sold in Denmark (the authors'): 3.5 and 0.1 wt-% fat, 3.4 wt-%
  // protein, homogenised at 20 MPa.
  out.push_back(milk_entry("whole_milk", "homogenised whole milk: 3.5 wt-% fat, 3.4 wt-% protein (20 MPa)",
                           {3.5, 3.4, 20.0}));
  out.push_back(milk_entry("skimmed_milk", "homogenised skimmed milk: 0.1 wt-% fat, 3.4 wt-% protein (20 MPa)",
                           {0.1, 3.4, 20.0}));
  for (const NarasimhanRow& r : parse_narasimhan(data::narasimhan2006)) out.push_back(narasimhan_entry(r));
  return out;
}

}  // namespace

const std::vector<ScatteringLibraryEntry>& scattering_media() {
  static const std::vector<ScatteringLibraryEntry> entries = load_entries();
  return entries;
}

const ScatteringLibraryEntry* find_scattering_medium(std::string_view name) {
  for (const ScatteringLibraryEntry& e : scattering_media())
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> scattering_medium_names() {
  std::vector<std::string> names;
  for (const ScatteringLibraryEntry& e : scattering_media()) names.push_back(e.name);
  return names;
}

}  // namespace bouguer
