#include "bouguer/scene/material_file.h"

#include <algorithm>
#include <sstream>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/core/csv.h"
#include "bouguer/core/limits.h"
#include "bouguer/spectra/spectrum_csv.h"
#include "bouguer/scene/values.h"

namespace bouguer {
namespace {

std::string trim(std::string s) {
  const auto not_space = [](unsigned char c) { return !std::isspace(c); };
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), not_space));
  s.erase(std::find_if(s.rbegin(), s.rend(), not_space).base(), s.end());
  return s;
}

struct HeaderLine {
  int line = 0;
  std::string key, value;
};

std::vector<HeaderLine> header_lines(const std::string& text) {
  std::vector<HeaderLine> out;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t[0] != '#') break;  // the header ends where the table starts
    const std::string body = trim(t.substr(1));
    const auto colon = body.find(':');
    if (colon == std::string::npos) continue;
    std::string key = trim(body.substr(0, colon));
    std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return std::tolower(c); });
    out.push_back({n, key, trim(body.substr(colon + 1))});
  }
  return out;
}

}  // namespace

bool has_unit_header(const std::filesystem::path& path) {
  for (const HeaderLine& h : header_lines(read_text_file(path)))
    if (h.key == "unit") return true;
  return false;
}

MaterialFile load_material_csv(const std::filesystem::path& path) {
  const std::string text = read_text_file(path);
  MaterialFile m;
  bool unit_seen = false;
  std::vector<std::string> seen;
  for (const HeaderLine& h : header_lines(text)) {
    const std::string where = fmt::format("{}:{}", path.string(), h.line);
    // A key given twice is ambiguous (which unit did the author mean?); other '#' lines are comments.
    const bool known = h.key == "unit" || h.key == "thickness" || h.key == "ior" || h.key == "name" ||
                       h.key == "description" || h.key == "source";
    if (known && std::find(seen.begin(), seen.end(), h.key) != seen.end())
      fail("{}: '{}' is given twice in the header", where, excerpt(h.key));
    if (known) seen.push_back(h.key);
    if (h.key == "unit") {
      const auto unit = absorption_unit_from_name(h.value);
      if (!unit)
        fail("{}: unknown unit '{}'{}", where, excerpt(h.value),
             suggestion(excerpt(h.value), {"attenuation_per_m", "absorbance_per_cm", "internal_transmittance",
                                  "molar_absorptivity", "extinction_coefficient"}));
      m.unit = *unit;
      unit_seen = true;
    } else if (h.key == "thickness") {
      if (h.value.size() > 40) fail("{}: thickness '{}' is not a length (write e.g. \"5 mm\")", where, excerpt(h.value));
      try {
        m.thickness_m = parse_length_m(h.value);
      } catch (const Error& e) {
        fail("{}: thickness: {}", where, e.what());
      }
      if (!(*m.thickness_m > 0.0)) fail("{}: thickness must be positive", where);
    } else if (h.key == "ior") {
      try {
        std::size_t used = 0;
        m.ior = std::stod(h.value, &used);
        if (used != h.value.size()) throw std::invalid_argument(h.value);
      } catch (const std::exception&) {
        fail("{}: ior '{}' is not a number", where, excerpt(h.value));
      }
      if (!(*m.ior >= 1.0 && *m.ior < 5.0)) fail("{}: a refractive index must be between 1 and 5", where);
    } else if (h.key == "name") {
      m.name = h.value;
    } else if (h.key == "description") {
      m.description = h.value;
    } else if (h.key == "source") {
      m.source = h.value;
    }
  }
  if (!unit_seen)
    fail("{}: no '# unit: ...' line before the table (attenuation_per_m, absorbance_per_cm, internal_transmittance, "
         "molar_absorptivity or extinction_coefficient)",
         path.string());
  if (m.unit == AbsorptionUnit::internal_transmittance && !m.thickness_m)
    fail("{}: unit internal_transmittance needs a '# thickness: ...' line", path.string());
  m.values = spectrum_from_csv(parse_csv(text, path.string()), 1);
  for (double v : m.values.value)
    if (v < 0.0) fail("{}: values must not be negative (got {})", path.string(), v);
  require_visible_overlap(m.values, path.string());
  if (m.name.empty()) m.name = path.stem().string();
  return m;
}

ResolvedMaterial resolve_material(const std::string& name_or_file, std::optional<double> concentration) {
  ResolvedMaterial r;
  if (concentration && *concentration < 0.0) fail("concentration must not be negative (got {})", *concentration);
  if (const LibraryMaterial* m = find_library_material(name_or_file)) {
    if (m->molar && !concentration) fail("'{}' is a solute: give --concentration in mol/L", m->name);
    r.name = std::string(m->name);
    r.library = m;
    r.molar = m->molar;
    r.concentration = concentration.value_or(1.0);
    r.sigma_a_per_m = scaled(m->sigma_a_per_m, r.concentration);
    r.ior = m->default_ior;
    if (const auto problem = beyond_limit(r.sigma_a_per_m, kMaxCoefficientPerM, "σ_a (per metre) at this concentration"))
      fail("{}: {}", m->name, *problem);
    return r;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(name_or_file, ec))
    fail("'{}' is neither a library material nor a file{}", name_or_file,
         suggestion(name_or_file, library_material_names()));
  MaterialFile f = load_material_csv(name_or_file);
  r.molar = f.unit == AbsorptionUnit::molar_absorptivity;
  if (r.molar && !concentration) fail("{}: unit molar_absorptivity needs --concentration in mol/L", name_or_file);
  r.concentration = concentration.value_or(1.0);
  r.name = f.name;
  r.ior = f.ior.value_or(1.5);
  r.sigma_a_per_m = to_sigma_a_per_m(f.values, f.unit, r.concentration, f.thickness_m, name_or_file);
  if (const auto problem = beyond_limit(r.sigma_a_per_m, kMaxCoefficientPerM, "σ_a (per metre) at this concentration"))
    fail("{}: {}", name_or_file, *problem);
  r.file = std::move(f);
  return r;
}

}  // namespace bouguer
