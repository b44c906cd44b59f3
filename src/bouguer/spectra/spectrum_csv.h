#pragma once
// Spectra from CSV tables with the header `wavelength_nm,<quantity>`.
#include <filesystem>
#include <string_view>

#include "bouguer/core/csv.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct SpectrumCsvRules {
  bool allow_negative = false;  // radiance, transmittance, absorption: never negative
};

// Column `column` (1 = the first after wavelength_nm) of a table as a spectrum. Errors name the
// source and line: wavelengths outside kMinWavelengthNm..kMaxWavelengthNm or not increasing, NaN,
// infinite or values beyond ±kMaxTableValue (core/limits.h), negative values where not allowed, a
// first column other than wavelength_nm.
TabulatedSpectrum spectrum_from_csv(const CsvTable& table, std::size_t column = 1, SpectrumCsvRules rules = {});

// A two-column spectrum file.
TabulatedSpectrum load_spectrum_csv(const std::filesystem::path& path, SpectrumCsvRules rules = {});

}  // namespace bouguer
