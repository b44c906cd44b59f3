#pragma once
// The built-in material library: measured (or, where stated, fitted) absorption spectra with
// their provenance. Tables are compiled in from data/materials (see data/README.md).
#include <string>
#include <string_view>
#include <vector>

#include "bouguer/media/ior.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct LibraryMaterial {
  std::string_view name;
  std::string_view description;  // which real material
  std::string_view measured;     // what was measured: quantity, path length, range; or "fitted model"
  std::string_view citation;
  double default_ior = 1.5;      // at the sodium d line
  // σ_a per metre as tabulated (1, 5 or 20 nm); for a solute (molar), per metre per mol/L, so the
  // scene's concentration is in mol/L and must be given.
  TabulatedSpectrum sigma_a_per_m;
  bool molar = false;
  double measured_min_nm = 360.0, measured_max_nm = 830.0;  // where the data is not extended
  // How values outside the measured range are made (empty: the data covers 360–830 nm).
  std::string_view extension;
  bool extended() const { return !extension.empty(); }
};

// nullptr for an unknown name.
const LibraryMaterial* find_library_material(std::string_view name);
std::vector<std::string> library_material_names();

}  // namespace bouguer
