#include "bouguer/scene/values.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <utility>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/core/limits.h"
#include "bouguer/spectra/spectrum_csv.h"
#include "bouguer/io/texture_image.h"
#include "bouguer/io/vdb.h"
#include "bouguer/media/absorption.h"
#include "bouguer/media/ior_library.h"
#include "bouguer/media/library.h"
#include "bouguer/media/medium.h"
#include "bouguer/media/scattering_library.h"
#include "bouguer/scene/material_file.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/rgb_to_spectrum.h"

namespace bouguer {
namespace {

// Each channel of a colour must not be negative.
Vec3 checked_rgb(const RgbInput& c, const Source& where, const char* what = "must not be negative") {
  for (std::size_t i = 0; i < 3; ++i)
    if (!(std::array{c.rgb.x, c.rgb.y, c.rgb.z}[i] >= 0.0)) where[i].fail("{}", what);
  return c.rgb;
}

// Unbounded RGB (a coefficient) lifted as pbrt-v4 lifts it: a sigmoid spectrum around 1/2,
// scaled by 2·max.
double lift_peak(const Vec3& rgb) { return std::max({rgb.x, rgb.y, rgb.z}); }

std::filesystem::path resolved(const std::filesystem::path& file, const Source& where) {
  return where.resolve(file.string());
}

// ---- media -------------------------------------------------------------------------------------

struct Absorption {
  Spectrum sigma_a_per_m;  // at the concentration given; with a field, at concentration 1 (ε)
  std::optional<double> library_ior;
  std::optional<ConcentrationField> field;
};

// {"unit": ..., "rgb": [r, g, b]}: an absorption known in RGB only, tabulated at 1 nm.
TabulatedSpectrum rgb_absorption_table(const RgbInput& c, const Source& where) {
  const Vec3 rgb = checked_rgb(c, where / "rgb");
  const double peak = lift_peak(rgb);
  if (peak == 0.0) return tabulate_visible([](double) { return 0.0; });
  const SigmoidPolynomial lifted = rgb_to_reflectance(rgb / (2.0 * peak));
  return tabulate_visible([&](double nm) { return 2.0 * peak * lifted(nm); });
}

Absorption library_absorption(const AbsorptionLibraryInput& in, const AbsorptionInput& a, double concentration,
                              const Source& where) {
  const LibraryMaterial* m = find_library_material(in.name);
  if (!m) (where / "library").fail("unknown material '{}'{}", in.name, suggestion(in.name, library_material_names()));
  if (m->molar && !a.concentration) where.fail("'{}' is a solute: give its 'concentration' in mol/L", in.name);
  return {scaled(m->sigma_a_per_m, concentration), m->default_ior, std::nullopt};
}

// A material file that names its own unit (scene/material_file.h).
Absorption file_absorption(const MaterialFileInput& in, const AbsorptionInput& a, double concentration,
                           const Source& where) {
  const std::filesystem::path path = resolved(in.csv, where);
  MaterialFile f;
  try {
    f = load_material_csv(path);
  } catch (const Error& e) {
    where.fail("{}", e.what());
  }
  if (f.unit == AbsorptionUnit::molar_absorptivity && !a.concentration)
    where.fail("{} is in molar_absorptivity: give 'concentration' in mol/L", path.string());
  return {to_sigma_a_per_m(f.values, f.unit, concentration, f.thickness_m, where.path), f.ior, std::nullopt};
}

// Values in a unit: a table, or RGB where only RGB data exist (lifted to a smooth spectrum as
// scattering RGB is, docs/scene-format.md), then converted from their unit.
Absorption values_absorption(const AbsorptionValuesInput& in, const AbsorptionInput& a, double concentration,
                             const Source& where) {
  const TabulatedSpectrum values = std::holds_alternative<RgbInput>(in.values)
                                       ? rgb_absorption_table(std::get<RgbInput>(in.values), where)
                                       : resolve_table(std::get<TableInput>(in.values), where);
  if (in.unit.empty())
    where.fail("needs 'unit' (attenuation_per_m, absorbance_per_cm, internal_transmittance, molar_absorptivity, "
               "extinction_coefficient) or 'library'");
  const auto unit = absorption_unit_from_name(in.unit);
  if (!unit) {
    const std::vector<std::string> units = {"attenuation_per_m", "absorbance_per_cm", "internal_transmittance",
                                            "molar_absorptivity", "extinction_coefficient"};
    (where / "unit").fail("unknown unit '{}'{}", in.unit, suggestion(in.unit, units));
  }
  if (*unit == AbsorptionUnit::molar_absorptivity && !a.concentration)
    where.fail("unit 'molar_absorptivity' needs 'concentration' in mol/L");
  std::optional<double> thickness;
  if (in.thickness) thickness = resolve_positive_length_m(*in.thickness, where / "thickness");
  try {
    return {to_sigma_a_per_m(values, *unit, concentration, thickness, where.path), std::nullopt, std::nullopt};
  } catch (const Error& e) {
    fail("{}: {}", where.file.string(), e.what());
  }
}

Absorption absorption(const AbsorptionInput& a, const Source& where) {
  double concentration = 1.0;
  const ConcentrationField* field = nullptr;
  if (a.concentration) {
    field = std::get_if<ConcentrationField>(&*a.concentration);
    if (!field) concentration = std::get<double>(*a.concentration);
    if (concentration < 0.0) (where / "concentration").fail("must not be negative (got {})", concentration);
  }
  Absorption out = std::visit(
      [&](const auto& source) -> Absorption {
        using T = std::decay_t<decltype(source)>;
        if constexpr (std::is_same_v<T, AbsorptionLibraryInput>) return library_absorption(source, a, concentration, where);
        else if constexpr (std::is_same_v<T, MaterialFileInput>) return file_absorption(source, a, concentration, where);
        else return values_absorption(source, a, concentration, where);
      },
      a.source);
  if (field) out.field = *field;
  return out;
}

// A density or concentration: a number (not negative), or a field.
ConcentrationField density_field(const ConcentrationInput& c, const Source& where) {
  if (const auto* f = std::get_if<ConcentrationField>(&c)) return *f;
  const double v = std::get<double>(c);
  if (v < 0.0) where.fail("must not be negative (got {})", v);
  return ConstantField{v};
}

// σ_s in a unit (natural log, per metre inside), or Rayleigh's λ⁻⁴ through one value.
Spectrum scattering_coefficient(const ScatteringValuesInput& in, const Source& where) {
  if (const auto* r = std::get_if<RayleighInput>(&in.values)) {
    const Source wr = where / "rayleigh";
    if (!(r->at_nm >= 200.0 && r->at_nm <= 2000.0)) (wr / "at_nm").fail("must lie between 200 and 2000 nm (got {})", r->at_nm);
    if (r->value_per_m < 0.0) (wr / "value_per_m").fail("σ_s must not be negative (got {})", r->value_per_m);
    const double at_nm = r->at_nm, value = r->value_per_m;
    return tabulate_visible([&](double nm) { return value * std::pow(at_nm / nm, 4.0); });
  }
  if (in.unit.empty())
    where.fail("needs 'unit' (attenuation_per_m, attenuation_per_cm or attenuation_per_mm), 'rayleigh' or 'library'");
  static const std::vector<std::pair<std::string, double>> kUnits = {
      {"attenuation_per_m", 1.0}, {"attenuation_per_cm", 100.0}, {"attenuation_per_mm", 1000.0}};
  const auto u = std::find_if(kUnits.begin(), kUnits.end(), [&](const auto& p) { return p.first == in.unit; });
  if (u == kUnits.end()) {
    std::vector<std::string> names;
    for (const auto& p : kUnits) names.push_back(p.first);
    (where / "unit").fail("unknown unit '{}'{} (σ_s is a natural-log coefficient)", in.unit, suggestion(in.unit, names));
  }
  if (const auto* c = std::get_if<RgbInput>(&in.values)) {
    const Vec3 rgb = checked_rgb(*c, where / "rgb", "σ_s must not be negative");
    const double peak = lift_peak(rgb);
    if (peak == 0.0) return ConstantSpectrum{0.0};
    return scaled(Spectrum{rgb_to_reflectance(rgb / (2.0 * peak))}, 2.0 * peak * u->second);
  }
  return scaled(Spectrum{resolve_table(std::get<TableInput>(in.values), where)}, u->second);
}

// `library` is set to the entry when the medium comes from the scattering library (its
// absorption and index are the medium's defaults).
ScatteringDesc scattering(const ScatteringInput& in, const Source& where, const ScatteringLibraryEntry*& library) {
  ScatteringDesc d;
  if (const auto* lib = std::get_if<ScatteringLibraryInput>(&in.source)) {
    const ScatteringLibraryEntry* e = find_scattering_medium(lib->name);
    if (!e)
      (where / "library").fail("unknown scattering medium '{}'{}", lib->name, suggestion(lib->name, scattering_medium_names()));
    d.sigma_s_per_m = e->sigma_s_per_m;
    d.phase = e->phase;
    if (max_value(e->sigma_a_per_m) > 0.0) d.sigma_a_per_m = e->sigma_a_per_m;
    library = e;
    if (lib->concentration) {
      // The library medium as a fraction of another liquid (a little milk in water): its σ_s and
      // σ_a scale, the host's `absorption` does not.
      if (in.density) where.fail("give either 'concentration' (of the library medium) or 'density', not both");
      d.density = density_field(*lib->concentration, where / "concentration");
      d.density_scales_absorption = false;
      return d;
    }
  } else {
    const auto& values = std::get<ScatteringValuesInput>(in.source);
    d.sigma_s_per_m = scattering_coefficient(values, where);
    d.phase = values.phase;
  }
  if (in.density) d.density = density_field(*in.density, where / "density");
  return d;
}

}  // namespace

// ---- lengths, tables, colours --------------------------------------------------------------------

namespace {
// A number and the unit after it ("5 mm" -> 5, "mm"); `noun` and `example` word the errors.
std::pair<double, std::string> number_and_unit(const std::string& s, const char* noun, const char* example) {
  std::size_t i = 0;
  while (i < s.size() && s[i] == ' ') ++i;
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data() + i, s.data() + s.size(), v);
  if (ec != std::errc()) fail("'{}' is not {} (write e.g. \"{}\")", s, noun, example);
  if (!std::isfinite(v)) fail("'{}' is not a finite {}", s, std::string(noun).substr(std::string(noun).find(' ') + 1));
  std::string unit(ptr, s.data() + s.size());
  unit.erase(std::remove(unit.begin(), unit.end(), ' '), unit.end());
  return {v, unit};
}
}  // namespace

double parse_length_m(const std::string& s) {
  const auto [v, unit] = number_and_unit(s, "a length", "5 mm");
  if (unit.empty()) fail("'{}' has no unit (write e.g. \"{} mm\"; nm, um, mm, cm, m, km)", s, s);
  static const std::vector<std::pair<std::string, double>> units = {
      {"nm", 1e-9}, {"um", 1e-6}, {"µm", 1e-6}, {"mm", 1e-3}, {"cm", 1e-2}, {"m", 1.0}, {"km", 1e3}};
  for (const auto& [name, factor] : units)
    if (unit == name) return v * factor;
  fail("'{}': unknown length unit '{}' (nm, um, mm, cm, m, km)", s, unit);
}

double parse_angle_rad(const std::string& s) {
  const auto [v, unit] = number_and_unit(s, "an angle", "30 deg");
  if (unit == "deg") return v * std::numbers::pi / 180.0;
  if (unit == "rad") return v;
  if (unit.empty()) fail("'{}' has no unit (write e.g. \"{} deg\"; deg, rad)", s, s);
  fail("'{}': unknown angle unit '{}' (deg, rad)", s, unit);
}

double resolve_length_m(const LengthInput& length, const Source& where) {
  double v = 0.0;
  if (const auto* m = std::get_if<double>(&length)) {
    v = *m;
    if (!std::isfinite(v)) where.fail("expected a finite number");
  } else {
    try {
      v = parse_length_m(std::get<std::string>(length));
    } catch (const Error& e) {
      where.fail("{}", e.what());
    }
  }
  if (!(std::abs(v) <= kMaxSceneCoordinateM)) where.fail("{:g} m is beyond the scene's extent of ±{:g} m", v, kMaxSceneCoordinateM);
  return v;
}

double resolve_positive_length_m(const LengthInput& length, const Source& where) {
  const double v = resolve_length_m(length, where);
  if (!(v > 0.0)) where.fail("must be a positive length (got {} m)", v);
  if (v < kMinSceneLengthM) where.fail("{:g} m is below the smallest length of {:g} m", v, kMinSceneLengthM);
  return v;
}

TabulatedSpectrum resolve_table(const TableInput& table, const Source& where, bool allow_negative) {
  if (table.csv) {
    const std::filesystem::path file = resolved(*table.csv, where);
    TabulatedSpectrum s = load_spectrum_csv(file, {.allow_negative = allow_negative});
    try {
      require_visible_overlap(s, file.string());
    } catch (const Error& e) {
      where.fail("{}", e.what());
    }
    return s;
  }
  TabulatedSpectrum s;
  try {
    s = make_tabulated(table.wavelength_nm, table.value, where.path);
  } catch (const Error& e) {
    fail("{}: {}", where.file.string(), e.what());
  }
  if (!allow_negative)
    for (double x : s.value)
      if (x < 0.0) (where / "value").fail("values must not be negative (got {})", x);
  try {
    require_visible_overlap(s, where.path);
  } catch (const Error& e) {
    fail("{}: {}", where.file.string(), e.what());
  }
  return s;
}

Spectrum resolve_spectral(const SpectralInput& value, const Source& where) {
  if (const auto* c = std::get_if<double>(&value)) return ConstantSpectrum{*c};
  return resolve_table(std::get<TableInput>(value), where);
}

// Named illuminants are normalised to luminance Y = scale; tables are taken in their own units
// times scale (normalised to Y = scale with "normalise": true).
EmissionDesc resolve_emission(const EmissionInput& in, const Source& where) {
  if (in.scale < 0.0) (where / "scale").fail("must not be negative (got {})", in.scale);
  EmissionDesc e;
  const Source ws = where / "spectrum";
  if (const auto* name = std::get_if<std::string>(&in.spectrum)) {
    const auto spd = named_illuminant_spd(*name);
    if (!spd) ws.fail("unknown illuminant '{}' (known: {})", *name, fmt::join(illuminant_names(), ", "));
    e.radiance = normalised_to_luminance(*spd, in.scale);
  } else if (const auto* c = std::get_if<RgbInput>(&in.spectrum)) {
    e.radiance = scaled(Spectrum{rgb_to_illuminant(checked_rgb(*c, ws / "rgb"))}, in.scale);
  } else if (const auto* texture = std::get_if<TextureInput>(&in.spectrum)) {
    e.radiance = scaled(Spectrum{rgb_to_illuminant({1.0, 1.0, 1.0})}, in.scale);
    e.texture = resolve_texture(*texture, ws, TextureUse::reflectance);
  } else {
    const Spectrum t = resolve_table(std::get<TableInput>(in.spectrum), ws);
    e.radiance = in.normalise ? normalised_to_luminance(t, in.scale) : scaled(t, in.scale);
  }
  e.two_sided = in.two_sided;
  return e;
}

IorModel resolve_ior(const IorInput& in, const Source& where) {
  if (const auto* n = std::get_if<double>(&in)) {
    if (!(*n >= 1.0 && *n < 5.0)) where.fail("a refractive index must be between 1 and 5 (got {})", *n);
    return ConstantIor{*n};
  }
  if (const auto* lib = std::get_if<IorLibraryInput>(&in)) {
    const IorLibraryEntry* e = find_ior_material(lib->name);
    if (!e) (where / "library").fail("unknown dispersion data '{}'{}", lib->name, suggestion(lib->name, ior_material_names()));
    return e->sellmeier;
  }
  if (const auto* abbe = std::get_if<AbbeInput>(&in)) {
    const Source wa = where / "abbe";
    if (!(abbe->n_d >= 1.0 && abbe->n_d < 5.0)) (wa / "n_d").fail("must be between 1 and 5");
    if (!(abbe->V_d >= 5.0 && abbe->V_d <= 200.0)) (wa / "V_d").fail("an Abbe number must be between 5 and 200");
    return cauchy_from_abbe(abbe->n_d, abbe->V_d);
  }
  if (const auto* s = std::get_if<SellmeierIor>(&in)) {
    const Source ws = where / "sellmeier";
    if (s->B.empty() || s->B.size() != s->C_um2.size()) ws.fail("'B' and 'C_um2' must have the same, non-zero length");
    for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0) {
      const double n = sellmeier_ior(*s, nm);
      if (!(n >= 1.0 && n < 5.0)) ws.fail("gives n = {} at {} nm; check the coefficients and units (C in µm²)", n, nm);
    }
    return *s;
  }
  if (const auto* c = std::get_if<CauchyIor>(&in)) {
    for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0)
      if (!(cauchy_ior(*c, nm) >= 1.0)) (where / "cauchy").fail("gives n < 1 at {} nm", nm);
    return *c;
  }
  TabulatedIor t{resolve_table(std::get<TableInput>(in), where)};
  for (double n : t.n.value)
    if (n < 1.0) where.fail("a refractive index must be at least 1 (got {})", n);
  return t;
}

// One absorber, or several whose σ_a add up (a dye diffusing into wine; a layered cocktail), then
// the scattering, then the index (given, or the first library part's).
MediumDesc resolve_medium(const std::string& name, const MediumInput& in, const Source& where) {
  MediumDesc m;
  m.name = name;
  std::optional<double> library_ior;
  const Source wa = where / "absorption";
  if (in.absorption_listed && (in.absorption.empty() || in.absorption.size() > kMaxAbsorbersPerMedium))
    wa.fail("needs 1 to {} absorbers (got {})", kMaxAbsorbersPerMedium, in.absorption.size());
  std::vector<Absorption> parts;
  for (std::size_t i = 0; i < in.absorption.size(); ++i)
    parts.push_back(absorption(in.absorption[i], in.absorption_listed ? wa[i] : wa));
  for (const Absorption& a : parts)
    if (!library_ior) library_ior = a.library_ior;
  if (parts.size() == 1 && !parts[0].field) {
    m.sigma_a_per_m = std::move(parts[0].sigma_a_per_m);
    m.absorbing = max_value(m.sigma_a_per_m) > 0.0;
  } else if (!parts.empty()) {
    for (Absorption& a : parts)
      m.field_absorbers.push_back({std::move(a.sigma_a_per_m), a.field.value_or(ConcentrationField{ConstantField{1.0}})});
    m.absorbing = true;
  }
  if (in.scattering) {
    const ScatteringLibraryEntry* library = nullptr;
    m.scattering = scattering(*in.scattering, where / "scattering", library);
    if (library && !library_ior) library_ior = library->ior;
  }
  if (in.ior) m.ior = resolve_ior(*in.ior, where / "ior");
  else if (library_ior) m.ior = ConstantIor{*library_ior};
  else where.fail("needs 'ior' (only library materials have a default)");
  return m;
}

namespace {

// "repeat", "clamp" or "mirror" (scene/texture.h's TextureWrap).
TextureWrap resolve_wrap(const std::string& name, const Source& where) {
  static const std::vector<std::string> names{"repeat", "clamp", "mirror"};
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) where.fail("unknown wrap '{}'{}", name, suggestion(name, names));
  constexpr std::array modes{TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror};
  return modes[static_cast<std::size_t>(it - names.begin())];
}

}  // namespace

TextureDesc resolve_texture(const TextureInput& texture, const Source& where, TextureUse use) {
  TextureDesc d{texture.file, texture.image, texture.transform, {}};
  const bool per_axis = texture.wrap[0] != texture.wrap[1];  // a pair in the file, or one name for both
  for (std::size_t i = 0; i < 2; ++i)
    d.sampler.wrap[i] = resolve_wrap(texture.wrap[i], per_axis ? (where / "wrap")[i] : where / "wrap");
  d.sampler.nearest_magnification = texture.nearest_magnification;
  const Source wf = where / "texture";
  if (!d.image) {
    d.file = wf.resolve(texture.file);
    try {
      d.image = std::make_shared<const TextureImage>(read_texture_image(d.file));
    } catch (const Error& e) {
      wf.fail("{}", e.what());  // the reader's line names the file; this one says where it was asked for
    }
  }
  if (use == TextureUse::colour || (use == TextureUse::reflectance && d.image->srgb)) return d;  // sRGB decodes into [0, 1]
  for (std::size_t i = 0; i < d.image->rgb.size(); ++i)
    if (d.image->rgb[i] < 0.0f || d.image->rgb[i] > 1.0f)
      wf.fail("{}: pixel ({}, {}) holds {}; {} must lie between 0 and 1", d.file.string(),
              i / 3 % static_cast<std::size_t>(d.image->width), i / 3 / static_cast<std::size_t>(d.image->width),
              d.image->rgb[i], use == TextureUse::reflectance ? "a reflectance" : "a data texel");
  return d;
}

std::vector<ObjectDesc> resolve_obj_materials(const ObjectDesc& base, const Source& where) {
  const auto* mesh = std::get_if<MeshShape>(&base.shape);
  if (!mesh || mesh->path.extension() != ".obj") where.fail("\"mtl\" takes the materials of an .obj mesh shape");
  ObjWithMaterials obj;
  try {
    obj = load_obj_materials(mesh->path, fmt::format("object '{}'", base.name));
  } catch (const Error& e) {
    where.fail("{}", e.what());
  }
  std::vector<ObjectDesc> out;
  for (const ObjPart& part : obj.parts) {
    ObjectDesc o = base;
    o.shape = TriangleMeshShape{part.mesh, part.mesh.normals, part.mesh.uvs, {}};
    DiffuseInput d;
    if (part.material >= 0) {
      const ObjMaterial& m = obj.materials[static_cast<std::size_t>(part.material)];
      o.name = fmt::format("{}: {}", base.name, m.name);
      if (m.map_kd.empty()) d.reflectance = RgbInput{m.kd};
      else d.reflectance = texture_file(m.map_kd.string());
    }
    o.material = resolve_surface_material(d, where);
    out.push_back(std::move(o));
  }
  return out;
}

namespace {

// An RGB reflectance, checked before the fit would clamp it: above 1 is a mistake.
Spectrum reflectance_rgb(const RgbInput& c, const Source& wr) {
  const Vec3 rgb = checked_rgb(c, wr / "rgb");
  for (std::size_t i = 0; i < 3; ++i)
    if (std::array{rgb.x, rgb.y, rgb.z}[i] > 1.0) (wr / "rgb")[i].fail("a reflectance must lie between 0 and 1");
  return Spectrum{rgb_to_reflectance(rgb)};
}

// A reflectance as a number, table, RGB or texture: into `spectrum`, or `texture` read instead.
void resolve_reflectance(const std::variant<double, TableInput, RgbInput, TextureInput>& in, const Source& wr,
                         Spectrum& spectrum, std::optional<TextureDesc>& texture) {
  if (const auto* c = std::get_if<RgbInput>(&in)) spectrum = reflectance_rgb(*c, wr);
  else if (const auto* v = std::get_if<double>(&in)) spectrum = ConstantSpectrum{*v};
  else if (const auto* t = std::get_if<TextureInput>(&in)) texture = resolve_texture(*t, wr, TextureUse::reflectance);
  else spectrum = resolve_table(std::get<TableInput>(in), wr);
}

MetallicRoughnessDesc resolve_metallic_roughness(const MetallicRoughnessInput& in, const Source& where) {
  MetallicRoughnessDesc d;
  const Source wb = where / "base_colour";
  if (const auto* t = std::get_if<TextureInput>(&in.base_colour))
    d.base_colour_texture = resolve_texture(*t, wb, TextureUse::reflectance);
  else
    d.base_colour = reflectance_rgb(std::get<RgbInput>(in.base_colour), wb);
  d.metalness = in.metalness;
  d.roughness = in.roughness;
  if (in.metallic_roughness_texture)
    d.metallic_roughness_texture = resolve_texture(*in.metallic_roughness_texture, where / "metallic_roughness",
                                                   TextureUse::data);
  return d;
}

}  // namespace

NormalMapDesc resolve_normal_map(const NormalMapInput& in, const Source& where) {
  if (!std::isfinite(in.scale)) (where / "scale").fail("must be a finite number");
  return {resolve_texture(in.texture, where, TextureUse::data), in.scale};
}

MaterialDesc resolve_surface_material(const MaterialInput& in, const Source& where) {
  if (const auto* c = std::get_if<ConductorInput>(&in)) {
    ConductorDesc d{resolve_spectral(c->n, where / "n"), resolve_spectral(c->k, where / "k"), c->roughness, std::nullopt};
    if (c->roughness_texture)
      d.roughness_texture = resolve_texture(*c->roughness_texture, where / "roughness", TextureUse::data);
    return d;
  }
  if (const auto* g = std::get_if<MetallicRoughnessInput>(&in)) return resolve_metallic_roughness(*g, where);
  if (const auto* t = std::get_if<ThinDielectricInput>(&in)) {
    ThinDielectricDesc d;
    d.ior = t->ior;  // its range checked by the builder
    if (t->tint) resolve_reflectance(*t->tint, where / "tint", d.tint, d.tint_texture);
    return d;
  }
  DiffuseDesc d;
  const auto& reflectance = std::get<DiffuseInput>(in).reflectance;
  if (reflectance) resolve_reflectance(*reflectance, where / "reflectance", d.reflectance, d.reflectance_texture);
  return d;
}

namespace {

Transform transform_step(const TransformStep& step, const Source& where) {
  if (const auto* s = std::get_if<ScaleStep>(&step)) {
    const Source ws = where / "scale";
    const Vec3 f = s->factor;
    if (!(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z))) ws.fail("must be finite");
    if (f.x == 0.0 || f.y == 0.0 || f.z == 0.0) ws.fail("a scale of zero collapses the shape");
    return Transform::scale(f);
  }
  if (const auto* r = std::get_if<RotateStep>(&step)) {
    const Source wr = where / "rotate_deg";
    if (!std::isfinite(r->angle_deg)) wr[0].fail("must be finite");
    if (!(std::isfinite(length(r->axis)) && length(r->axis) > 0.0)) wr[1].fail("the rotation axis must not be zero");
    return Transform::rotate_deg(r->angle_deg, r->axis);
  }
  if (const auto* t = std::get_if<TranslateStep>(&step)) {
    const Vec3 o = t->offset_m;
    if (!(std::abs(o.x) <= kMaxSceneCoordinateM && std::abs(o.y) <= kMaxSceneCoordinateM &&
          std::abs(o.z) <= kMaxSceneCoordinateM))
      (where / "translate").fail("must lie within the scene's extent of ±{:g} m", kMaxSceneCoordinateM);
    return Transform::translate(o);
  }
  const auto& rows = std::get<MatrixStep>(step).rows;
  const Source wm = where / "matrix";
  for (std::size_t r = 0; r < 4; ++r)
    for (std::size_t c = 0; c < 4; ++c)
      if (!std::isfinite(rows[r][c])) wm[r][c].fail("must be finite");
  if (rows[3][0] != 0.0 || rows[3][1] != 0.0 || rows[3][2] != 0.0 || rows[3][3] != 1.0)
    wm[3].fail("the last row of an affine matrix must be [0, 0, 0, 1]");
  Transform m;
  for (std::size_t r = 0; r < 3; ++r) {
    for (std::size_t c = 0; c < 3; ++c) m.linear.m[r][c] = rows[r][c];
    m.translation[r] = rows[r][3];
  }
  if (m.determinant() == 0.0) wm.fail("the matrix is singular");
  return m;
}

void check_concentration(double c, const Source& where) {
  if (!(c >= 0.0) || !std::isfinite(c)) where.fail("a concentration must not be negative (got {})", c);
}

void check_axis(const FieldAxis& a, const Source& where) {
  if (!(std::abs(length(a.axis) - 1.0) <= 1e-9)) (where / "axis").fail("must be a direction of finite, non-zero length");
  if (!(std::isfinite(length(a.origin_m)))) (where / "origin").fail("must be finite");
}

}  // namespace

Transform resolve_transform(const std::vector<TransformStep>& steps, const Source& where) {
  Transform t;
  for (std::size_t i = 0; i < steps.size(); ++i) t = t.then(transform_step(steps[i], where[i]));
  return t;
}

GridField resolve_grid_field(const GridFieldInput& in, const Source& where) {
  const std::filesystem::path file = where.resolve(in.file);
  VdbGrid g;
  try {
    g = read_vdb_grid(file, in.grid);
  } catch (const VdbError& e) {
    (where / (e.in_grid ? "grid" : "file")).fail("{}", e.what());
  }
  const Transform to_world = Transform{g.world_per_index, g.node_origin_m}.then(in.placement);
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 node{corner & 1 ? g.values.nodes[0] - 1.0 : 0.0, corner & 2 ? g.values.nodes[1] - 1.0 : 0.0,
                    corner & 4 ? g.values.nodes[2] - 1.0 : 0.0};
    const Vec3 x = to_world.apply(node);
    if (!(std::abs(x.x) <= kMaxSceneCoordinateM && std::abs(x.y) <= kMaxSceneCoordinateM &&
          std::abs(x.z) <= kMaxSceneCoordinateM))
      (where / "grid").fail("{}: the grid reaches ({:g}, {:g}, {:g}) m, beyond the scene's extent of ±{:g} m",
                            file.string(), x.x, x.y, x.z, kMaxSceneCoordinateM);
  }
  const double det = to_world.determinant();
  if (!(std::isfinite(det) && std::abs(det) > 0.0))
    (where / "grid").fail("{}: the grid's index-to-world map is singular", file.string());
  const Mat3 index_per_m = inverse(to_world.linear);
  GridField f{std::make_shared<const GridValues>(std::move(g.values)), index_per_m,
              -(index_per_m * to_world.translation), in.scale};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(f.index_per_m.m[r][c]))
        (where / "grid").fail("{}: the grid's voxels are too small to invert their map", file.string());
  return f;
}

void check_concentration_field(const ConcentrationField& field, const Source& where) {
  std::visit(
      [&](const auto& f) {
        using T = std::decay_t<decltype(f)>;
        if constexpr (std::is_same_v<T, ConstantField>) {
          if (!(f.value >= 0.0) || !std::isfinite(f.value)) where.fail("must not be negative (got {})", f.value);
        } else if constexpr (std::is_same_v<T, GridField>) {
          if (!(f.scale >= 0.0) || !std::isfinite(f.scale)) (where / "scale").fail("must not be negative (got {})", f.scale);
          if (!f.values) where.fail("a grid field needs its values (resolve_grid_field reads them)");
        } else if constexpr (std::is_same_v<T, LayersField>) {
          check_axis(f.frame, where);
          const Source wl = where / "layers";
          if (f.upper_s_m.empty() || f.upper_s_m.size() > kMaxLayers || f.value.size() != f.upper_s_m.size())
            wl.fail("needs 1 to {} layers (got {})", kMaxLayers, f.upper_s_m.size());
          for (std::size_t i = 0; i < f.upper_s_m.size(); ++i) {
            if (!(std::abs(f.upper_s_m[i]) <= kMaxSceneCoordinateM))
              wl[i][0].fail("{:g} m is beyond the scene's extent of ±{:g} m", f.upper_s_m[i], kMaxSceneCoordinateM);
            if (i > 0 && !(f.upper_s_m[i] > f.upper_s_m[i - 1]))
              wl[i][0].fail("layer bounds must increase ({:g} m follows {:g} m)", f.upper_s_m[i], f.upper_s_m[i - 1]);
            check_concentration(f.value[i], wl[i][1]);
          }
        } else {
          check_axis(f.frame, where);
          check_concentration(f.value, where / "value");
          if constexpr (std::is_same_v<T, LinearField>) {
            if (!std::isfinite(f.slope_per_m)) (where / "slope_per_m").fail("must be finite");
          } else if constexpr (std::is_same_v<T, ExponentialField>) {
            if (!(f.scale_length_m >= kMinSceneLengthM && f.scale_length_m <= kMaxSceneCoordinateM))
              (where / "scale_length").fail("must be a positive length of at most {:g} m (got {:g} m)",
                                            kMaxSceneCoordinateM, f.scale_length_m);
          } else {
            if (!(f.width_m >= kMinSceneLengthM && f.width_m <= kMaxSceneCoordinateM))
              (where / "width").fail("the diffusion width {:g} m is outside {:g} to {:g} m", f.width_m, kMinSceneLengthM,
                                     kMaxSceneCoordinateM);
          }
        }
      },
      field);
}

}  // namespace bouguer
