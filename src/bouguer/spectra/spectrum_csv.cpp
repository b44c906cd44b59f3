#include "bouguer/spectra/spectrum_csv.h"

#include <cmath>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/core/limits.h"

namespace bouguer {

TabulatedSpectrum spectrum_from_csv(const CsvTable& table, std::size_t column, SpectrumCsvRules rules) {
  if (table.columns.front() != "wavelength_nm")
    fail("{}: the first column must be 'wavelength_nm' (found '{}')", table.source,
         excerpt(table.columns.front()));
  if (column == 0 || column >= table.columns.size())
    fail("{}: expected a column after wavelength_nm (header 'wavelength_nm,<quantity>')", table.source);
  TabulatedSpectrum s;
  const std::string name = excerpt(table.columns[column]);
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    const double nm = table.rows[i][0];
    const double value = table.rows[i][column];
    const int line = table.line[i];
    if (!(nm >= kMinWavelengthNm && nm <= kMaxWavelengthNm))
      fail("{}, line {}: wavelength_nm must be a positive number of nanometres from {} to {} (found {})", table.source, line,
           kMinWavelengthNm, kMaxWavelengthNm, nm);
    if (!s.wavelength_nm.empty() && nm <= s.wavelength_nm.back())
      fail("{}, line {}: wavelength {} nm does not increase (previous row: {} nm)", table.source, line, nm,
           s.wavelength_nm.back());
    if (!std::isfinite(value)) fail("{}, line {}: {} is not a finite number", table.source, line, name);
    if (std::abs(value) > kMaxTableValue)
      fail("{}, line {}: {} is {}, beyond the ±{} a table value may have (docs/limits.md)", table.source, line, name,
           value, kMaxTableValue);
    if (value < 0.0 && !rules.allow_negative)
      fail("{}, line {}: {} is negative ({}); it must be zero or more", table.source, line, name, value);
    s.wavelength_nm.push_back(nm);
    s.value.push_back(value);
  }
  return s;
}

TabulatedSpectrum load_spectrum_csv(const std::filesystem::path& path, SpectrumCsvRules rules) {
  const CsvTable table = read_csv_file(path);
  if (table.columns.size() != 2)
    fail("{}: expected two columns 'wavelength_nm,<quantity>', found {}", table.source, table.columns.size());
  return spectrum_from_csv(table, 1, rules);
}

}  // namespace bouguer
