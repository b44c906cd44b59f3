#pragma once
// The built-in library of scattering media (#12), each with what was measured and by whom:
// σ_s and σ_a (natural log, per metre), a Henyey-Greenstein phase function and the index of the
// liquid. Entries measured in RGB only are lifted to smooth spectra and flagged as such.
#include <string>
#include <string_view>
#include <vector>

#include "bouguer/media/phase.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct ScatteringLibraryEntry {
  std::string name;
  std::string description;  // which real medium, at which concentration
  std::string measured;     // what was measured or computed, and how
  std::string citation;
  double ior = 1.333;       // of the liquid, at the sodium d line
  Spectrum sigma_a_per_m = ConstantSpectrum{0.0};
  Spectrum sigma_s_per_m = ConstantSpectrum{0.0};
  PhaseFunction phase = IsotropicPhase{};
  bool rgb_measured = false;  // only three RGB values exist: the spectra are lifted from them
};

// nullptr for an unknown name.
const ScatteringLibraryEntry* find_scattering_medium(std::string_view name);
std::vector<std::string> scattering_medium_names();
const std::vector<ScatteringLibraryEntry>& scattering_media();

}  // namespace bouguer
