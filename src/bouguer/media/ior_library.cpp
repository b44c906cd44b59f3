#include "bouguer/media/ior_library.h"

#include <array>

namespace bouguer {
namespace {

// Coefficients as the database pages give them; formula-1 pages (C in µm) are squared here to µm².
const std::array<IorLibraryEntry, 6> kEntries = {{
    {"N-BK7", "SCHOTT N-BK7 borosilicate crown glass",
     "SCHOTT Zemax catalogue 2017-01-20b via refractiveindex.info (specs/schott/optical/N-BK7.yml)",
     {{1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653}}},
    {"F2", "SCHOTT F2 lead flint glass",
     "SCHOTT Zemax catalogue 2017-01-20b via refractiveindex.info (specs/schott/optical/F2.yml)",
     {{1.34533359, 0.209073176, 0.937357162}, {0.00997743871, 0.0470450767, 111.886764}}},
    {"N-SF11", "SCHOTT N-SF11 dense flint glass",
     "SCHOTT Zemax catalogue 2017-01-20b via refractiveindex.info (specs/schott/optical/N-SF11.yml)",
     {{1.73759695, 0.313747346, 1.89878101}, {0.013188707, 0.0623068142, 155.23629}}},
    {"fused-silica", "fused silica (SiO2), 20 °C",
     "I. H. Malitson, J. Opt. Soc. Am. 55, 1205 (1965), via refractiveindex.info (main/SiO2/nk/Malitson.yml)",
     {{0.6961663, 0.4079426, 0.8974794}, {0.0684043 * 0.0684043, 0.1162414 * 0.1162414, 9.896161 * 9.896161}}},
    {"water", "distilled water, 20 °C",
     "M. Daimon, A. Masumura, Appl. Opt. 46, 3811 (2007), via refractiveindex.info (main/H2O/nk/Daimon-20.0C.yml)",
     {{5.684027565e-1, 1.726177391e-1, 2.086189578e-2, 1.130748688e-1},
      {5.101829712e-3, 1.821153936e-2, 2.620722293e-2, 1.069792721e1}}},
    {"diamond", "diamond (C)",
     "F. Peter, Z. Phys. 15, 358 (1923), via refractiveindex.info (main/C/nk/Peter.yml); measured 226-760 nm",
     {{0.3306, 4.3356}, {0.1750 * 0.1750, 0.1060 * 0.1060}}},
}};

}  // namespace

const IorLibraryEntry* find_ior_material(std::string_view name) {
  for (const auto& e : kEntries)
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> ior_material_names() {
  std::vector<std::string> names;
  for (const auto& e : kEntries) names.emplace_back(e.name);
  return names;
}

CauchyIor cauchy_from_abbe(double n_d, double v_d) {
  constexpr double d = 0.58756, f = 0.48613, c = 0.65627;  // µm
  const double b = (n_d - 1.0) / (v_d * (1.0 / (f * f) - 1.0 / (c * c)));
  return {n_d - b / (d * d), b, 0.0};
}

}  // namespace bouguer
