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
  TabulatedSpectrum sigma_a_per_m;  // as tabulated (1 or 5 nm), covering 360–830 nm
};

// nullptr for an unknown name.
const LibraryMaterial* find_library_material(std::string_view name);
std::vector<std::string> library_material_names();

}  // namespace bouguer
