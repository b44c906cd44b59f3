#pragma once
// Built-in dispersion data (Sellmeier formulas) for common transparent materials, from the
// refractiveindex.info database (CC0; M. N. Polyanskiy, Scientific Data 11, 94 (2024)) and the
// original measurements each entry cites.
#include <string>
#include <string_view>
#include <vector>

#include "bouguer/media/ior.h"

namespace bouguer {

struct IorLibraryEntry {
  std::string_view name;
  std::string_view description;
  std::string_view citation;
  SellmeierIor sellmeier;
};

const IorLibraryEntry* find_ior_material(std::string_view name);
std::vector<std::string> ior_material_names();

// n(λ) = A + B/λ² through n_d at 587.56 nm with Abbe number V_d = (n_d − 1)/(n_F − n_C),
// n_F at 486.13 nm and n_C at 656.27 nm.
CauchyIor cauchy_from_abbe(double n_d, double v_d);

}  // namespace bouguer
