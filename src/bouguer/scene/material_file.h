#pragma once
// Materials the user brings: a CSV spectrum with a small header naming its unit, in '#' comment
// lines of the form `key: value` before the table:
//   # unit: absorbance_per_cm      required: attenuation_per_m, absorbance_per_cm,
//                                  internal_transmittance, molar_absorptivity, extinction_coefficient
//   # thickness: 2 mm              for internal_transmittance: the thickness it was measured at
//   # ior: 1.49                    optional refractive index (default 1.5)
//   # name: / description: / source:   optional free text
//   wavelength_nm,value
//   380,0.12
// The scene file reads the same files ({"absorption": {"csv": "my-glass.csv"}}) and
// `bouguer material my-glass.csv` analyses them; both go through load_material_csv.
#include <filesystem>
#include <optional>
#include <string>

#include "bouguer/media/absorption.h"
#include "bouguer/media/library.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct MaterialFile {
  TabulatedSpectrum values;  // in `unit`
  AbsorptionUnit unit = AbsorptionUnit::attenuation_per_m;
  std::optional<double> thickness_m;
  std::optional<double> ior;
  std::string name, description, source;
};

// Errors name the file and line.
MaterialFile load_material_csv(const std::filesystem::path& path);

// Whether a CSV file declares its unit in such a header.
bool has_unit_header(const std::filesystem::path& path);

// A material to analyse or render: σ_a per metre with the concentration applied, the refractive
// index, and where it came from.
struct ResolvedMaterial {
  std::string name;
  Spectrum sigma_a_per_m;
  double ior = 1.5;
  bool molar = false;
  double concentration = 1.0;           // mol/L for molar materials, otherwise a relative factor
  const LibraryMaterial* library = nullptr;  // set for library materials
  std::optional<MaterialFile> file;         // set for files
};

// A library name or a material CSV file. Molar materials need a concentration; an unknown name
// that is not a file is an Error with the nearest library name suggested.
ResolvedMaterial resolve_material(const std::string& name_or_file, std::optional<double> concentration);

}  // namespace bouguer
