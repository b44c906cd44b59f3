#include "bouguer/scene/loader.h"

#include "bouguer/scene/gltf.h"
#include "bouguer/scene/pbr_material.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <nlohmann/json.hpp>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/core/csv.h"
#include "bouguer/io/json.h"
#include "bouguer/core/limits.h"
#include "bouguer/media/medium.h"
#include "bouguer/scene/builder.h"
#include "bouguer/scene/nested.h"
#include "bouguer/scene/values.h"

namespace bouguer {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

// Where a value sits in the file: the file name and the key path, for messages.
using Where = Source;

std::string type_name(const json& j) { return j.type_name(); }

void expect_keys(const json& j, const Where& w, const std::vector<std::string>& allowed) {
  if (!j.is_object()) w.fail("expected an object {{...}}, found {}", type_name(j));
  for (const auto& [key, value] : j.items()) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    (w / key).fail("unknown key{}", suggestion(key, allowed));
  }
}

double number(const json& j, const Where& w) {
  if (!j.is_number()) w.fail("expected a number, found {}", type_name(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) w.fail("expected a finite number");
  return v;
}

// A whole number for the builder, which checks its range (any value a 64-bit integer holds).
std::int64_t whole_number(const json& j, const Where& w) {
  if (!j.is_number_integer()) w.fail("expected a whole number, found {}", type_name(j));
  if (j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX))
    w.fail("{} is beyond the largest whole number, {}", j.get<std::uint64_t>(), INT64_MAX);
  return j.get<std::int64_t>();
}

int integer(const json& j, const Where& w, int lo, int hi) {
  if (!j.is_number_integer()) w.fail("expected a whole number, found {}", type_name(j));
  // An unsigned value above the range of long long would wrap in get<long long>().
  if (j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(hi))
    w.fail("must be between {} and {} (got {})", lo, hi, j.get<std::uint64_t>());
  const auto v = j.get<long long>();
  if (v < lo || v > hi) w.fail("must be between {} and {} (got {})", lo, hi, v);
  return static_cast<int>(v);
}

std::string text(const json& j, const Where& w) {
  if (!j.is_string()) w.fail("expected a string, found {}", type_name(j));
  return j.get<std::string>();
}

bool boolean(const json& j, const Where& w) {
  if (!j.is_boolean()) w.fail("expected true or false, found {}", type_name(j));
  return j.get<bool>();
}

const json& array(const json& j, const Where& w, std::size_t size = 0) {
  if (!j.is_array()) w.fail("expected an array [...], found {}", type_name(j));
  if (size && j.size() != size) w.fail("expected {} elements, found {}", size, j.size());
  return j;
}

// A length: metres, or a string with a unit; its meaning and range are the builder's (values.h).
LengthInput length_input(const json& j, const Where& w) {
  if (j.is_number()) return number(j, w);
  if (!j.is_string()) w.fail("expected a length (metres, or a string such as \"5 mm\"), found {}", type_name(j));
  return j.get<std::string>();
}

double length_m(const json& j, const Where& w) { return resolve_length_m(length_input(j, w), w); }
double positive_length_m(const json& j, const Where& w) { return resolve_positive_length_m(length_input(j, w), w); }

Vec3 vec3(const json& j, const Where& w) {
  array(j, w, 3);
  return {number(j[0], w[0]), number(j[1], w[1]), number(j[2], w[2])};
}

// A direction (up, a light's direction, a rotation axis): any length but zero, finite when squared.
Vec3 direction(const json& j, const Where& w) {
  const Vec3 d = vec3(j, w);
  if (!(std::isfinite(length(d)) && length(d) > 0.0)) w.fail("must be a direction of finite, non-zero length");
  return d;
}

Vec3 length_vec3(const json& j, const Where& w) {
  array(j, w, 3);
  return {length_m(j[0], w[0]), length_m(j[1], w[1]), length_m(j[2], w[2])};
}

std::vector<double> numbers(const json& j, const Where& w) {
  array(j, w);
  std::vector<double> out;
  for (std::size_t i = 0; i < j.size(); ++i) out.push_back(number(j[i], w[i]));
  return out;
}

// {"rgb": [r, g, b]}: a linear Rec.709 colour (checked and lifted by the builder).
RgbInput rgb_input(const json& j, const Where& w) { return {vec3(j["rgb"], w / "rgb")}; }

// {"wavelength_nm": [...], "value": [...]} or {"csv": "file.csv"}: the table form shared by
// absorption, IOR, reflectance and emission data. `extra` lists the caller's other keys.
TableInput table_input(const json& j, const Where& w, std::vector<std::string> extra) {
  extra.insert(extra.end(), {"wavelength_nm", "value", "csv"});
  expect_keys(j, w, extra);
  TableInput t;
  if (j.contains("csv")) {
    if (j.contains("wavelength_nm") || j.contains("value")) w.fail("give either 'csv' or 'wavelength_nm'/'value'");
    t.csv = text(j["csv"], w / "csv");
    return t;
  }
  if (!j.contains("wavelength_nm") || !j.contains("value")) w.fail("needs 'wavelength_nm' and 'value' arrays (or 'csv')");
  t.wavelength_nm = numbers(j["wavelength_nm"], w / "wavelength_nm");
  t.value = numbers(j["value"], w / "value");
  return t;
}

// "wrap": "clamp" (both axes) or ["repeat", "mirror"] (along u, along v): names, which the
// builder checks (resolve_texture).
std::array<std::string, 2> wrap_names(const json& j, const Where& w) {
  if (j.is_string()) return {j.get<std::string>(), j.get<std::string>()};
  if (!j.is_array() || j.size() != 2) w.fail("expected a wrap name or two ([along u, along v])");
  return {text(j[0], w[0]), text(j[1], w[1])};
}

// {"texture": "label.png", "wrap": "clamp", "transform": {"offset": [u, v], "rotation": "30 deg",
// "scale": [su, sv]}}: an image file (read by the builder), how it wraps outside [0, 1], and a
// transform of its texture coordinates in Bouguer's v-up convention (uv_transform_v_up,
// scene/texture.h). `extra` lists the caller's other keys.
TextureInput texture_input(const json& j, const Where& w, std::vector<std::string> extra = {}) {
  extra.insert(extra.end(), {"texture", "transform", "wrap"});
  expect_keys(j, w, extra);
  TextureInput t = texture_file(text(j["texture"], w / "texture"));
  if (j.contains("wrap")) t.wrap = wrap_names(j["wrap"], w / "wrap");
  if (!j.contains("transform")) return t;
  const Where wt = w / "transform";
  const json& tj = j["transform"];
  expect_keys(tj, wt, {"offset", "rotation", "scale"});
  auto pair = [&](const char* key, std::array<double, 2> fallback) {
    if (!tj.contains(key)) return fallback;
    array(tj[key], wt / key, 2);
    return std::array<double, 2>{number(tj[key][0], (wt / key)[0]), number(tj[key][1], (wt / key)[1])};
  };
  double rotation_rad = 0.0;
  if (tj.contains("rotation")) {
    try {
      rotation_rad = parse_angle_rad(text(tj["rotation"], wt / "rotation"));
    } catch (const Error& e) {
      (wt / "rotation").fail("{}", e.what());
    }
  }
  const std::array<double, 2> scale = pair("scale", {1.0, 1.0});
  for (std::size_t i = 0; i < 2; ++i)
    if (scale[i] == 0.0) (wt / "scale")[i].fail("must not be 0 (it would map the surface to one line of texels)");
  t.transform = uv_transform_v_up(pair("offset", {0.0, 0.0}), rotation_rad, scale);
  return t;
}

// ---- spectra, media ---------------------------------------------------------------------------

// {"spectrum": "D65" | {"rgb": [...]} | table, "scale": s, "normalise": b, "two_sided": b}; an
// emitter's (allow_two_sided) spectrum may also be {"texture": ...}.
EmissionInput emission_input(const json& j, const Where& w, bool allow_two_sided) {
  std::vector<std::string> keys = {"spectrum", "scale", "normalise"};
  if (allow_two_sided) keys.push_back("two_sided");
  expect_keys(j, w, keys);
  EmissionInput e;
  if (j.contains("scale")) e.scale = number(j["scale"], w / "scale");
  if (!j.contains("spectrum")) w.fail("needs 'spectrum' (a named illuminant such as \"D65\", or a table)");
  const json& s = j["spectrum"];
  const Where ws = w / "spectrum";
  if (s.is_string()) {
    e.spectrum = s.get<std::string>();
  } else if (s.is_object() && s.contains("rgb")) {
    expect_keys(s, ws, {"rgb"});
    e.spectrum = rgb_input(s, ws);
  } else if (s.is_object() && s.contains("texture")) {
    if (!allow_two_sided) ws.fail("only an emitting object takes a texture");
    e.spectrum = texture_input(s, ws);
  } else {
    e.spectrum = table_input(s, ws, {});
  }
  if (j.contains("normalise")) e.normalise = boolean(j["normalise"], w / "normalise");
  if (j.contains("two_sided")) e.two_sided = boolean(j["two_sided"], w / "two_sided");
  return e;
}

EmissionDesc emission(const json& j, const Where& w, bool allow_two_sided) {
  return resolve_emission(emission_input(j, w, allow_two_sided), w);
}

// {"environment": "sky.exr", "scale": 1, "rotate_deg": 0}: a lat-long map (lights/environment.h).
EnvironmentDesc environment(const json& j, const Where& w) {
  expect_keys(j, w, {"environment", "scale", "rotate_deg"});
  EnvironmentDesc e;
  e.file = w.resolve(text(j["environment"], w / "environment"));
  if (j.contains("scale")) e.scale = number(j["scale"], w / "scale");
  if (j.contains("rotate_deg")) e.rotate_deg = number(j["rotate_deg"], w / "rotate_deg");
  return e;
}

IorInput ior_input(const json& j, const Where& w) {
  if (j.is_number()) return number(j, w);
  if (!j.is_object()) w.fail("expected a number or an object (library, sellmeier, cauchy, abbe, table)");
  if (j.contains("library")) {
    expect_keys(j, w, {"library"});
    return IorLibraryInput{text(j["library"], w / "library")};
  }
  if (j.contains("abbe")) {
    expect_keys(j, w, {"abbe"});
    const Where wa = w / "abbe";
    expect_keys(j["abbe"], wa, {"n_d", "V_d"});
    if (!j["abbe"].contains("n_d") || !j["abbe"].contains("V_d")) wa.fail("needs 'n_d' and 'V_d'");
    return AbbeInput{number(j["abbe"]["n_d"], wa / "n_d"), number(j["abbe"]["V_d"], wa / "V_d")};
  }
  if (j.contains("sellmeier")) {
    expect_keys(j, w, {"sellmeier"});
    const Where ws = w / "sellmeier";
    expect_keys(j["sellmeier"], ws, {"B", "C_um2"});
    if (!j["sellmeier"].contains("B") || !j["sellmeier"].contains("C_um2")) ws.fail("needs 'B' and 'C_um2'");
    return SellmeierIor{numbers(j["sellmeier"]["B"], ws / "B"), numbers(j["sellmeier"]["C_um2"], ws / "C_um2")};
  }
  if (j.contains("cauchy")) {
    expect_keys(j, w, {"cauchy"});
    const Where wc = w / "cauchy";
    expect_keys(j["cauchy"], wc, {"A", "B_um2", "C_um4"});
    CauchyIor c;
    if (!j["cauchy"].contains("A")) wc.fail("needs 'A'");
    c.A = number(j["cauchy"]["A"], wc / "A");
    if (j["cauchy"].contains("B_um2")) c.B_um2 = number(j["cauchy"]["B_um2"], wc / "B_um2");
    if (j["cauchy"].contains("C_um4")) c.C_um4 = number(j["cauchy"]["C_um4"], wc / "C_um4");
    return c;
  }
  return table_input(j, w, {});
}

Transform transform(const json& j, const Where& w);

// {"field": "grid", "file": "dye.vdb", "grid": "density", "scale": 1, "transform": [...]}: an
// OpenVDB float grid (io/vdb.h), placed by its own index-to-world map and then the transform;
// read and checked by the builder's resolve_grid_field.
GridField grid_field(const json& j, const Where& w) {
  expect_keys(j, w, {"field", "file", "grid", "scale", "transform"});
  if (!j.contains("file")) w.fail("a grid field needs 'file' (an OpenVDB .vdb file)");
  GridFieldInput in;
  in.file = text(j["file"], w / "file");
  if (j.contains("grid")) in.grid = text(j["grid"], w / "grid");
  if (j.contains("scale")) in.scale = number(j["scale"], w / "scale");
  if (j.contains("transform")) in.placement = transform(j["transform"], w / "transform");
  return resolve_grid_field(in, w);
}

// {"field": "linear" | "exponential" | "diffusion" | "layers", "origin": [...], "axis": [...], ...}:
// a concentration that varies along an axis (media/concentration_field.h, docs/scene-format.md),
// or {"field": "grid", ...}, a voxel grid. Its values are the builder's to check
// (check_concentration_field), as for every front end.
ConcentrationField concentration_field(const json& j, const Where& w) {
  static const std::vector<std::string> kinds = {"linear", "exponential", "diffusion", "layers", "grid"};
  if (!j.is_object() || !j.contains("field")) w.fail("a concentration field needs 'field' ({})", fmt::join(kinds, ", "));
  const std::string kind = text(j["field"], w / "field");
  if (kind == "grid") return grid_field(j, w);
  auto keys = [&](std::vector<std::string> own) {
    own.insert(own.end(), {"field", "origin", "axis"});
    expect_keys(j, w, own);
  };
  auto frame = [&] {
    FieldAxis a;
    if (j.contains("origin")) a.origin_m = length_vec3(j["origin"], w / "origin");
    if (j.contains("axis")) a.axis = normalize(direction(j["axis"], w / "axis"));
    return a;
  };
  auto value = [&] {
    if (!j.contains("value")) w.fail("a {} field needs 'value' (the concentration at the origin)", kind);
    return number(j["value"], w / "value");
  };
  if (kind == "linear") {
    keys({"value", "slope_per_m"});
    if (!j.contains("slope_per_m")) w.fail("a linear field needs 'slope_per_m' (concentration per metre along the axis)");
    return LinearField{frame(), value(), number(j["slope_per_m"], w / "slope_per_m")};
  }
  if (kind == "exponential") {
    keys({"value", "scale_length"});
    if (!j.contains("scale_length")) w.fail("an exponential field needs 'scale_length' (H in c0·exp(−s/H))");
    return ExponentialField{frame(), value(), length_m(j["scale_length"], w / "scale_length")};
  }
  if (kind == "diffusion") {
    keys({"value", "width", "diffusivity_m2_per_s", "time_s"});
    const bool by_time = j.contains("diffusivity_m2_per_s") || j.contains("time_s");
    if (j.contains("width") == by_time)
      w.fail("a diffusion field needs either 'width' (w in erfc(s/w)) or 'diffusivity_m2_per_s' and 'time_s'");
    if (!by_time) return DiffusionField{frame(), value(), length_m(j["width"], w / "width")};
    // The scene file's own way of giving the width, w = 2·sqrt(D·t); the width is the builder's to check.
    if (!j.contains("diffusivity_m2_per_s") || !j.contains("time_s"))
      w.fail("give both 'diffusivity_m2_per_s' and 'time_s' (w = 2·sqrt(D·t))");
    const double d = number(j["diffusivity_m2_per_s"], w / "diffusivity_m2_per_s");
    const double t = number(j["time_s"], w / "time_s");
    if (!(d > 0.0)) (w / "diffusivity_m2_per_s").fail("must be positive (got {})", d);
    if (!(t > 0.0)) (w / "time_s").fail("must be positive (got {})", t);
    return DiffusionField{frame(), value(), 2.0 * std::sqrt(d * t)};
  }
  if (kind == "layers") {
    keys({"layers"});
    if (!j.contains("layers")) w.fail("a layers field needs 'layers' [[upper bound, concentration], ...]");
    const Where wl = w / "layers";
    const json& layers = array(j["layers"], wl);
    LayersField f{frame(), {}, {}};
    for (std::size_t i = 0; i < layers.size(); ++i) {
      array(layers[i], wl[i], 2);
      f.upper_s_m.push_back(length_m(layers[i][0], wl[i][0]));
      f.value.push_back(number(layers[i][1], wl[i][1]));
    }
    return f;
  }
  (w / "field").fail("unknown concentration field '{}'{}", kind, suggestion(kind, kinds));
}

// A concentration or density: a number, or a field.
ConcentrationInput concentration_input(const json& j, const Where& w) {
  if (j.is_object()) return concentration_field(j, w);
  return number(j, w);
}

AbsorptionInput absorption_input(const json& j, const Where& w) {
  if (!j.is_object()) w.fail("expected an object with 'library' or 'unit'");
  AbsorptionInput a;
  if (j.contains("concentration")) a.concentration = concentration_input(j["concentration"], w / "concentration");
  if (j.contains("library")) {
    expect_keys(j, w, {"library", "concentration"});
    a.source = AbsorptionLibraryInput{text(j["library"], w / "library")};
  } else if (j.contains("csv") && !j.contains("unit")) {
    // A material file that names its own unit (scene/material_file.h).
    expect_keys(j, w, {"csv", "concentration"});
    a.source = MaterialFileInput{text(j["csv"], w / "csv")};
  } else {
    AbsorptionValuesInput v;
    if (j.contains("rgb")) {
      expect_keys(j, w, {"unit", "rgb", "concentration", "thickness"});
      v.values = rgb_input(j, w);
    } else {
      v.values = table_input(j, w, {"unit", "concentration", "thickness"});
    }
    if (j.contains("unit")) v.unit = text(j["unit"], w / "unit");
    if (j.contains("thickness")) v.thickness = length_input(j["thickness"], w / "thickness");
    a.source = std::move(v);
  }
  return a;
}

PhaseFunction phase_function(const json& j, const Where& w) {
  if (!j.is_object() || !j.contains("type")) w.fail("needs 'type' (isotropic or henyey_greenstein)");
  const std::string type = text(j["type"], w / "type");
  if (type == "isotropic") {
    expect_keys(j, w, {"type"});
    return IsotropicPhase{};
  }
  if (type == "henyey_greenstein") {
    expect_keys(j, w, {"type", "g"});
    if (!j.contains("g")) w.fail("a Henyey-Greenstein phase function needs 'g' (the mean cosine, −1 < g < 1)");
    return HenyeyGreensteinPhase{number(j["g"], w / "g")};  // g checked by the builder
  }
  (w / "type").fail("unknown phase function '{}'{}", type, suggestion(type, {"isotropic", "henyey_greenstein"}));
}

ScatteringInput scattering_input(const json& j, const Where& w) {
  if (!j.is_object()) w.fail("expected an object with 'unit' and σ_s values, 'rayleigh' or 'library'");
  ScatteringInput in;
  if (j.contains("library")) {
    expect_keys(j, w, {"library", "concentration", "density"});
    ScatteringLibraryInput lib{text(j["library"], w / "library"), std::nullopt};
    if (j.contains("concentration")) lib.concentration = concentration_input(j["concentration"], w / "concentration");
    in.source = std::move(lib);
  } else {
    expect_keys(j, w, {"unit", "wavelength_nm", "value", "csv", "rgb", "rayleigh", "phase", "density"});
    ScatteringValuesInput v;
    if (j.contains("rayleigh")) {
      const Where wr = w / "rayleigh";
      const json& r = j["rayleigh"];
      if (!r.is_object()) wr.fail("expected an object with 'at_nm' and 'value_per_m'");
      expect_keys(r, wr, {"at_nm", "value_per_m"});
      if (!r.contains("at_nm") || !r.contains("value_per_m")) wr.fail("needs 'at_nm' and 'value_per_m' (σ_s there)");
      v.values = RayleighInput{number(r["at_nm"], wr / "at_nm"), number(r["value_per_m"], wr / "value_per_m")};
    } else {
      if (!j.contains("unit"))
        w.fail("needs 'unit' (attenuation_per_m, attenuation_per_cm or attenuation_per_mm), 'rayleigh' or 'library'");
      v.unit = text(j["unit"], w / "unit");
      if (j.contains("rgb")) v.values = rgb_input(j, w);
      else v.values = table_input(j, w, {"unit", "phase", "density"});
    }
    if (j.contains("phase")) v.phase = phase_function(j["phase"], w / "phase");
    in.source = std::move(v);
  }
  if (j.contains("density")) in.density = concentration_input(j["density"], w / "density");
  return in;
}

MediumInput medium_input(const json& j, const Where& w) {
  expect_keys(j, w, {"ior", "absorption", "scattering"});
  MediumInput m;
  if (j.contains("absorption")) {
    // One absorber, or a list whose σ_a add up (a dye diffusing into wine; a layered cocktail).
    const Where wa = w / "absorption";
    if (j["absorption"].is_array()) {
      const json& list = array(j["absorption"], wa);
      m.absorption_listed = true;
      for (std::size_t i = 0; i < list.size(); ++i) m.absorption.push_back(absorption_input(list[i], wa[i]));
    } else {
      m.absorption.push_back(absorption_input(j["absorption"], wa));
    }
  }
  if (j.contains("scattering")) m.scattering = scattering_input(j["scattering"], w / "scattering");
  if (j.contains("ior")) m.ior = ior_input(j["ior"], w / "ior");
  return m;
}

SpectralInput spectral_input(const json& j, const Where& w) {
  if (j.is_number()) return number(j, w);
  return table_input(j, w, {});
}

// A reflectance (a diffuse one, a thin sheet's tint): a number, {"rgb": ...}, a texture or a table.
std::variant<double, TableInput, RgbInput, TextureInput> reflectance_input(const json& r, const Where& wr) {
  if (r.is_object() && r.contains("rgb")) {
    expect_keys(r, wr, {"rgb"});
    return rgb_input(r, wr);
  }
  if (r.is_object() && r.contains("texture")) return texture_input(r, wr);
  if (r.is_number()) return number(r, wr);
  return table_input(r, wr, {});
}

MaterialDesc material(const json& j, const Where& w) {
  if (!j.is_object() || !j.contains("type")) w.fail("needs 'type' (diffuse, conductor or thin_dielectric)");
  const std::string type = text(j["type"], w / "type");
  if (type == "diffuse") {
    expect_keys(j, w, {"type", "reflectance"});
    DiffuseInput d;
    if (j.contains("reflectance")) d.reflectance = reflectance_input(j["reflectance"], w / "reflectance");
    return resolve_surface_material(d, w);
  }
  if (type == "thin_dielectric") {
    expect_keys(j, w, {"type", "ior", "tint"});
    ThinDielectricInput t;
    if (j.contains("ior")) t.ior = number(j["ior"], w / "ior");
    if (j.contains("tint")) t.tint = reflectance_input(j["tint"], w / "tint");
    return resolve_surface_material(t, w);  // its ranges checked by the builder
  }
  if (type == "conductor") {
    expect_keys(j, w, {"type", "n", "k", "roughness"});
    if (!j.contains("n") || !j.contains("k")) w.fail("a conductor needs 'n' and 'k' (numbers or tables)");
    ConductorInput c{spectral_input(j["n"], w / "n"), spectral_input(j["k"], w / "k"), 0.0, std::nullopt};
    if (j.contains("roughness")) {
      const json& r = j["roughness"];
      if (r.is_object()) c.roughness_texture = texture_input(r, w / "roughness");  // GGX alpha per texel
      else c.roughness = number(r, w / "roughness");
    }
    return resolve_surface_material(c, w);  // its ranges checked by the builder
  }
  (w / "type").fail("unknown material '{}' (diffuse, conductor, thin_dielectric)", type);
}

// "normal_map": "bumps.png", or {"texture": "bumps.png", "scale": 1, "transform": {...}}.
NormalMapInput normal_map_input(const json& j, const Where& w) {
  if (j.is_string()) return {texture_file(j.get<std::string>()), 1.0};
  if (!j.is_object() || !j.contains("texture")) w.fail("expected a file name or {{\"texture\": ..., \"scale\": ...}}");
  NormalMapInput n{texture_input(j, w, {"scale"}), 1.0};
  if (j.contains("scale")) n.scale = number(j["scale"], w / "scale");
  return n;
}

// ---- shapes, transforms ---------------------------------------------------------------------

std::vector<std::array<double, 2>> profile(const json& j, const Where& w) {
  array(j, w);
  std::vector<std::array<double, 2>> p;
  for (std::size_t i = 0; i < j.size(); ++i) {
    array(j[i], w[i], 2);
    p.push_back({length_m(j[i][0], w[i][0]), length_m(j[i][1], w[i][1])});
  }
  return p;
}

Shape shape(const json& j, const Where& w, const MeshArrays* arrays) {
  if (!j.is_object() || !j.contains("type")) w.fail("needs 'type'");
  const std::string type = text(j["type"], w / "type");
  auto get_len = [&](const char* k, double def) { return j.contains(k) ? positive_length_m(j[k], w / k) : def; };
  auto need_len = [&](const char* k) {
    if (!j.contains(k)) w.fail("a {} needs '{}'", type, k);
    return positive_length_m(j[k], w / k);
  };
  auto get_int = [&](const char* k, int def, int lo, int hi) { return j.contains(k) ? integer(j[k], w / k, lo, hi) : def; };
  auto get_num = [&](const char* k, double def) { return j.contains(k) ? number(j[k], w / k) : def; };
  auto get_bool = [&](const char* k) { return j.contains(k) && boolean(j[k], w / k); };
  if (type == "quad") {
    expect_keys(j, w, {"type", "size"});
    if (!j.contains("size")) w.fail("a quad needs 'size' [width, height]");
    array(j["size"], w / "size", 2);
    return QuadShape{positive_length_m(j["size"][0], (w / "size")[0]), positive_length_m(j["size"][1], (w / "size")[1])};
  }
  if (type == "disk") {
    expect_keys(j, w, {"type", "radius", "segments", "tessellate"});
    return DiskShape{need_len("radius"), get_int("segments", 128, 3, 4096), get_bool("tessellate")};
  }
  if (type == "box") {
    expect_keys(j, w, {"type", "size"});
    if (!j.contains("size")) w.fail("a box needs 'size' [x, y, z]");
    const Vec3 s = length_vec3(j["size"], w / "size");
    for (int i = 0; i < 3; ++i)
      if (!(s[i] > 0.0)) (w / "size")[i].fail("must be a positive length (got {} m)", s[i]);
    return BoxShape{s};
  }
  if (type == "sphere") {
    expect_keys(j, w, {"type", "radius", "segments", "tessellate"});
    return SphereShape{need_len("radius"), get_int("segments", 96, 3, 4096), get_bool("tessellate")};
  }
  if (type == "cylinder") {
    expect_keys(j, w, {"type", "radius", "height", "segments", "tessellate"});
    return CylinderShape{need_len("radius"), need_len("height"), get_int("segments", 128, 3, 4096),
                         get_bool("tessellate")};
  }
  if (type == "prism" || type == "pyramid") {
    expect_keys(j, w, {"type", "sides", "radius", "height"});
    const int sides = get_int("sides", 6, 3, 1024);
    if (type == "prism") return PrismShape{sides, need_len("radius"), need_len("height")};
    return PyramidShape{sides, need_len("radius"), need_len("height")};
  }
  if (type == "truncated_cube") {
    expect_keys(j, w, {"type", "size", "truncation"});
    return TruncatedCubeShape{need_len("size"), get_num("truncation", 0.29289321881345254)};
  }
  if (type == "brilliant") {
    expect_keys(j, w, {"type", "diameter", "table", "crown_angle_deg", "pavilion_angle_deg", "girdle"});
    return BrilliantShape{need_len("diameter"), get_num("table", 0.57), get_num("crown_angle_deg", 34.5),
                          get_num("pavilion_angle_deg", 40.75), get_num("girdle", 0.03)};
  }
  if (type == "lathe") {
    expect_keys(j, w, {"type", "profile", "segments", "crease_angle_deg"});
    if (!j.contains("profile")) w.fail("a lathe needs 'profile' [[r, y], ...]");
    return LatheShape{profile(j["profile"], w / "profile"), get_int("segments", 128, 3, 4096),
                      get_num("crease_angle_deg", kDefaultCreaseAngleDeg)};
  }
  if (type == "vessel") {
    expect_keys(j, w, {"type", "profile", "wall", "fill", "segments", "crease_angle_deg"});
    if (!j.contains("profile")) w.fail("a vessel needs 'profile' [[r, y], ...]");
    return VesselShape{profile(j["profile"], w / "profile"), get_len("wall", 0.002), get_num("fill", 0.0),
                       get_int("segments", 128, 3, 4096), get_num("crease_angle_deg", kDefaultCreaseAngleDeg)};
  }
  if (type == "mesh") {
    expect_keys(j, w, {"type", "file", "arrays"});
    if (j.contains("file") == j.contains("arrays"))
      w.fail("a mesh needs either 'file' (.obj or .ply) or 'arrays' (a mesh given to load_dict)");
    if (j.contains("file")) return MeshShape{w.resolve(text(j["file"], w / "file"))};
    // Triangles a front end handed over in memory (Python's load_dict(meshes=...)), checked there.
    const std::string name = text(j["arrays"], w / "arrays");
    if (arrays == nullptr) (w / "arrays").fail("meshes given as arrays exist only in Python's load_dict(meshes=...)");
    const auto it = arrays->find(name);
    if (it == arrays->end()) {
      std::vector<std::string> names;
      for (const auto& [n, m] : *arrays) names.push_back(n);
      (w / "arrays").fail("no mesh '{}' was given{}", name, suggestion(name, names));
    }
    return it->second;
  }
  const std::vector<std::string> types = {"quad", "disk", "box", "sphere", "cylinder", "prism", "pyramid",
                                          "truncated_cube", "brilliant", "lathe", "vessel", "mesh"};
  (w / "type").fail("unknown shape '{}'{}", type, suggestion(type, types));
}

// The steps as the file gives them; their checks and composition are the builder's
// (resolve_transform).
Transform transform(const json& j, const Where& w) {
  array(j, w);
  std::vector<TransformStep> steps;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const Where wi = w[i];
    expect_keys(j[i], wi, {"scale", "rotate_deg", "translate", "matrix"});
    if (j[i].size() != 1) wi.fail("each step has exactly one of scale, rotate_deg, translate, matrix");
    const auto step_it = j[i].begin();  // the step's one key (items() would dangle here)
    const std::string key = step_it.key();
    const json& v = step_it.value();
    const Where wv = wi / key;
    if (key == "scale") {
      steps.emplace_back(ScaleStep{v.is_number() ? Vec3{1, 1, 1} * number(v, wv) : vec3(v, wv)});
    } else if (key == "rotate_deg") {
      array(v, wv, 2);
      steps.emplace_back(RotateStep{number(v[0], wv[0]), vec3(v[1], wv[1])});
    } else if (key == "translate") {
      steps.emplace_back(TranslateStep{length_vec3(v, wv)});
    } else {
      array(v, wv, 4);
      MatrixStep m;
      for (std::size_t r = 0; r < 4; ++r) {
        array(v[r], wv[r], 4);
        for (std::size_t c = 0; c < 4; ++c) m.rows[r][c] = number(v[r][c], wv[r][c]);
      }
      steps.emplace_back(m);
    }
  }
  return resolve_transform(steps, w);
}

// ---- top level ---------------------------------------------------------------------------------

void read_camera(const json& j, const Where& w, SceneBuilder& b) {
  expect_keys(j, w, {"type", "position", "look_at", "up", "fov_deg", "width", "shift", "resolution"});
  CameraDesc c;
  if (j.contains("type")) {
    const std::string t = text(j["type"], w / "type");
    if (t == "pinhole") c.type = CameraType::pinhole;
    else if (t == "orthographic") c.type = CameraType::orthographic;
    else (w / "type").fail("unknown camera '{}' (pinhole, orthographic)", t);
  }
  if (j.contains("position")) c.position_m = length_vec3(j["position"], w / "position");
  if (j.contains("look_at")) c.look_at_m = length_vec3(j["look_at"], w / "look_at");
  if (j.contains("up")) c.up = vec3(j["up"], w / "up");  // checked by the builder
  if (j.contains("fov_deg")) c.fov_deg = number(j["fov_deg"], w / "fov_deg");
  if (j.contains("width")) c.width_m = positive_length_m(j["width"], w / "width");
  if (j.contains("shift")) {
    const Where ws = w / "shift";
    array(j["shift"], ws, 2);
    c.shift_x = number(j["shift"][0], ws[0]), c.shift_y = number(j["shift"][1], ws[1]);
  }
  b.camera(c, w);
  if (j.contains("resolution")) {
    const Where wr = w / "resolution";
    array(j["resolution"], wr, 2);
    b.resolution(whole_number(j["resolution"][0], wr[0]), whole_number(j["resolution"][1], wr[1]), wr);
  }
}

void read_render_settings(const json& j, const Where& w, SceneBuilder& b) {
  expect_keys(j, w,
              {"integrator", "spectral", "spp", "max_depth", "seed", "merge_radius", "exit_guide", "manifold",
               "area_lamp_chains", "guiding", "light_paths", "shell_transport"});
  if (j.contains("integrator")) b.integrator(text(j["integrator"], w / "integrator"), w / "integrator");
  if (j.contains("spectral")) b.spectral_mode(text(j["spectral"], w / "spectral"), w / "spectral");
  if (j.contains("spp")) b.spp(whole_number(j["spp"], w / "spp"), w / "spp");
  if (j.contains("max_depth")) b.max_depth(whole_number(j["max_depth"], w / "max_depth"), w / "max_depth");
  if (j.contains("seed")) b.seed(whole_number(j["seed"], w / "seed"), w / "seed");
  if (j.contains("merge_radius")) b.merge_radius(positive_length_m(j["merge_radius"], w / "merge_radius"), w / "merge_radius");
  if (j.contains("exit_guide")) b.exit_guide(boolean(j["exit_guide"], w / "exit_guide"));
  if (j.contains("manifold")) b.manifold(boolean(j["manifold"], w / "manifold"));
  if (j.contains("area_lamp_chains")) b.area_lamp_chains(boolean(j["area_lamp_chains"], w / "area_lamp_chains"));
  if (j.contains("guiding")) b.guiding(boolean(j["guiding"], w / "guiding"));
  if (j.contains("light_paths")) b.light_paths(boolean(j["light_paths"], w / "light_paths"));
  if (j.contains("shell_transport")) b.shell_transport(boolean(j["shell_transport"], w / "shell_transport"));
}

// "display": exposure, white balance and display curve (io/display.h, docs/scene-format.md).
void read_display(const json& j, const Where& w, SceneBuilder& b) {
  expect_keys(j, w,
              {"exposure_ev", "auto_exposure", "camera_exposure", "white_balance", "curve", "expose_float_outputs"});
  if (j.contains("exposure_ev")) b.exposure_ev(number(j["exposure_ev"], w / "exposure_ev"), w / "exposure_ev");
  if (j.contains("auto_exposure")) b.auto_exposure(boolean(j["auto_exposure"], w / "auto_exposure"));
  if (j.contains("camera_exposure")) {
    const Where wc = w / "camera_exposure";
    if (j.contains("auto_exposure") && b.auto_exposure_on())
      wc.fail("excludes 'auto_exposure': true; give one of them");
    expect_keys(j["camera_exposure"], wc, {"iso", "shutter_s", "f_number"});
    for (const char* key : {"iso", "shutter_s", "f_number"})
      if (!j["camera_exposure"].contains(key)) wc.fail("needs 'iso', 'shutter_s' and 'f_number' (missing '{}')", key);
    const json& c = j["camera_exposure"];
    b.camera_exposure({number(c["iso"], wc / "iso"), number(c["shutter_s"], wc / "shutter_s"),
                       number(c["f_number"], wc / "f_number")},
                      wc);
  }
  if (j.contains("white_balance")) b.white_balance(text(j["white_balance"], w / "white_balance"), w / "white_balance");
  if (j.contains("curve")) b.display_curve(text(j["curve"], w / "curve"), w / "curve");
  if (j.contains("expose_float_outputs"))
    b.expose_float_outputs(boolean(j["expose_float_outputs"], w / "expose_float_outputs"));
}

DeltaLightDesc delta_light(const json& j, const Where& w) {
  expect_keys(j, w,
              {"type", "position", "look_at", "direction", "cone_deg", "falloff_deg", "spectrum", "scale", "radius"});
  if (!j.contains("type")) w.fail("needs 'type' (point, spot, distant)");
  const std::string type = text(j["type"], w / "type");
  DeltaLightDesc l;
  if (type == "point") l.type = DeltaLightType::point;
  else if (type == "spot") l.type = DeltaLightType::spot;
  else if (type == "distant") l.type = DeltaLightType::distant;
  else (w / "type").fail("unknown light '{}'{}", type, suggestion(type, {"point", "spot", "distant"}));
  if (l.type != DeltaLightType::distant) {
    if (!j.contains("position")) w.fail("a {} light needs 'position'", type);
    l.position_m = length_vec3(j["position"], w / "position");
  }
  if (l.type != DeltaLightType::point) {
    if (j.contains("direction") == j.contains("look_at")) w.fail("give either 'direction' or 'look_at'");
    const Vec3 d = j.contains("direction") ? direction(j["direction"], w / "direction")
                                           : length_vec3(j["look_at"], w / "look_at") - l.position_m;
    if (length(d) == 0.0) w.fail("the light's direction is zero");
    l.direction = normalize(d);
  }
  if (l.type == DeltaLightType::spot) {
    if (j.contains("cone_deg")) l.cone_deg = number(j["cone_deg"], w / "cone_deg");
    l.falloff_deg = j.contains("falloff_deg") ? number(j["falloff_deg"], w / "falloff_deg") : 0.8 * l.cone_deg;
  }
  if (j.contains("radius")) l.radius_m = positive_length_m(j["radius"], w / "radius");  // the builder: spots only
  // The same spectrum keys as an emitter: named illuminants are scaled to Y = scale.
  json spectrum_keys = json::object();
  for (const char* k : {"spectrum", "scale"})
    if (j.contains(k)) spectrum_keys[k] = j[k];
  l.intensity = emission(spectrum_keys, w, false).radiance;
  return l;
}

ObjectDesc object(const json& j, const Where& w, std::size_t index, const MeshArrays* arrays) {
  expect_keys(j, w,
              {"name", "shape", "transform", "inside", "outside", "contents", "emission", "material", "roughness",
               "priority"});
  ObjectDesc o;
  o.name = j.contains("name") ? text(j["name"], w / "name") : fmt::format("object {}", index);
  if (!j.contains("shape")) w.fail("needs 'shape'");
  o.shape = shape(j["shape"], w / "shape", arrays);
  if (j.contains("transform")) o.transform = transform(j["transform"], w / "transform");
  if (j.contains("inside")) o.inside = text(j["inside"], w / "inside");
  if (j.contains("outside")) o.outside = text(j["outside"], w / "outside");
  if (j.contains("contents")) o.contents = text(j["contents"], w / "contents");
  if (j.contains("emission")) o.emission = emission(j["emission"], w / "emission", true);
  if (j.contains("material") && j["material"].is_string()) {
    if (j["material"] != "mtl") (w / "material").fail("expected an object, or \"mtl\" (the OBJ's own materials)");
  } else if (j.contains("material")) {
    const Where wm = w / "material";
    if (j["material"].is_object() && j["material"].contains("normal_map")) {
      json m = j["material"];
      o.normal_map = resolve_normal_map(normal_map_input(m["normal_map"], wm / "normal_map"), wm / "normal_map");
      m.erase("normal_map");
      o.material = material(m, wm);
    } else {
      o.material = material(j["material"], wm);
    }
  }
  if (j.contains("roughness")) o.roughness = number(j["roughness"], w / "roughness");
  if (j.contains("priority")) o.priority = whole_number(j["priority"], w / "priority");
  return o;  // its roles and media are checked by the builder
}

// "pbr": glTF's metallic-roughness material with its extensions' values (docs/scene-format.md), the
// role the glTF reader gives an asset's materials, through the same mapping (scene/pbr_material.h).
PbrMaterialInput pbr_input(const json& j, const Where& w) {
  if (!j.is_object()) w.fail("expected an object of material values (base_color, metallic, roughness, ...)");
  expect_keys(j, w,
              {"base_color", "base_color_texture", "metallic", "roughness", "metallic_roughness_texture", "emission",
               "emission_strength", "emission_texture", "transmission", "thin_walled", "ior", "dispersion",
               "attenuation_color", "attenuation_distance"});
  PbrMaterialInput m;
  auto num = [&](const char* key, double& out) {
    if (j.contains(key)) out = number(j[key], w / key);
  };
  auto colour = [&](const char* key, Vec3& out) {
    if (j.contains(key)) out = vec3(j[key], w / key);
  };
  auto texture = [&](const char* key, std::optional<TextureInput>& out) {
    if (j.contains(key)) out = texture_input(j[key], w / key);
  };
  colour("base_color", m.base_color);
  texture("base_color_texture", m.base_color_texture);
  num("metallic", m.metallic);
  num("roughness", m.roughness);
  texture("metallic_roughness_texture", m.metallic_roughness_texture);
  colour("emission", m.emissive);
  num("emission_strength", m.emissive_strength);
  texture("emission_texture", m.emissive_texture);
  num("transmission", m.transmission);
  if (j.contains("thin_walled")) m.thin_walled = boolean(j["thin_walled"], w / "thin_walled");
  num("ior", m.ior);
  num("dispersion", m.dispersion);
  colour("attenuation_color", m.attenuation_color);
  if (j.contains("attenuation_distance")) m.attenuation_distance_m = length_m(j["attenuation_distance"], w / "attenuation_distance");
  return m;
}

// An object whose role is a "pbr" material. A transmissive solid bounds the medium `inside` names
// (a scene's measured medium: a Blender material's volume), or else one made of the material's
// own ior and attenuation, named "<object> (pbr)".
void add_pbr_object(SceneBuilder& b, const json& j, const Where& w, std::size_t index, const MeshArrays* arrays) {
  if (j.contains("material") || j.contains("emission")) w.fail("give either 'pbr' or 'material'/'emission', not both");
  json rest = j;
  rest.erase("pbr");
  ObjectDesc o = object(rest, w, index, arrays);
  const Where wp = w / "pbr";
  PbrRole role = pbr_role(pbr_input(j["pbr"], wp), wp);
  o.emission = std::move(role.emission);
  o.material = std::move(role.material);
  if (role.volume) {
    if (!j.contains("roughness")) o.roughness = role.interface_roughness;
    if (!o.inside) {
      o.inside = fmt::format("{} (pbr)", o.name);
      b.medium(*o.inside, *role.volume, wp);
    }
  } else if (o.inside) {
    (w / "inside").fail("belongs to a transmissive 'pbr' material (transmission above 0, not thin-walled)");
  }
  b.object(std::move(o), w);
}

// {"gltf": "bottle.glb", "name": "bottle", "transform": [...], "materials": {"Glass": {"inside": "glass"}}}:
// an asset's primitives as objects (named "bottle: nodes[2] meshes[0].primitives[1]"), its materials
// overridden by name with an object's roles.
GltfObjectInput gltf_object(const json& j, const Where& w) {
  expect_keys(j, w, {"gltf", "name", "transform", "materials"});
  GltfObjectInput in;
  in.file = w.resolve(text(j["gltf"], w / "gltf"));
  if (j.contains("name")) in.name = text(j["name"], w / "name");
  if (j.contains("transform")) in.transform = transform(j["transform"], w / "transform");
  if (j.contains("materials")) {
    const Where wm = w / "materials";
    if (!j["materials"].is_object()) wm.fail("expected an object of glTF material names");
    for (const auto& [name, m] : j["materials"].items()) {
      const Where wn = wm / name;
      expect_keys(m, wn, {"inside", "outside", "material", "emission", "roughness", "priority"});
      GltfMaterialOverride ov;
      if (m.contains("inside")) ov.inside = text(m["inside"], wn / "inside");
      if (m.contains("outside")) ov.outside = text(m["outside"], wn / "outside");
      if (m.contains("material")) ov.material = material(m["material"], wn / "material");
      if (m.contains("emission")) ov.emission = emission(m["emission"], wn / "emission", true);
      if (m.contains("roughness")) ov.roughness = number(m["roughness"], wn / "roughness");
      if (m.contains("priority")) ov.priority = whole_number(m["priority"], wn / "priority");
      in.materials[name] = ov;
    }
  }
  return in;
}

}  // namespace

static void read_scene(const std::string& json_text, const fs::path& path, SceneBuilder& b,
                       const MeshArrays* arrays = nullptr) {
  const json root = parse_json(json_text, path);
  const Where top{path, ""};
  expect_keys(root, top, {"camera", "render", "display", "world_medium", "media", "objects", "lights", "background"});
  if (root.contains("camera")) read_camera(root["camera"], top / "camera", b);
  // A scene that names no estimator has it chosen by trials (integrators/choose.h).
  b.integrator("auto", top / "render");
  if (root.contains("render")) read_render_settings(root["render"], top / "render", b);
  if (root.contains("display")) read_display(root["display"], top / "display", b);
  if (root.contains("world_medium")) b.world_medium(text(root["world_medium"], top / "world_medium"), top / "world_medium");
  if (root.contains("media")) {
    const Where wm = top / "media";
    if (!root["media"].is_object()) wm.fail("expected an object of named media");
    for (const auto& [name, m] : root["media"].items()) b.medium(name, medium_input(m, wm / name), wm / name);
  }
  if (!root.contains("objects")) top.fail("needs 'objects'");
  const Where wo = top / "objects";
  array(root["objects"], wo);
  for (std::size_t i = 0; i < root["objects"].size(); ++i) {
    const json& o = root["objects"][i];
    if (o.is_object() && o.contains("gltf")) {
      add_gltf_objects(b, gltf_object(o, wo[i]), wo[i]);
    } else if (o.is_object() && o.contains("pbr")) {
      add_pbr_object(b, o, wo[i], i, arrays);
    } else if (o.is_object() && o.contains("material") && o["material"] == "mtl") {
      for (ObjectDesc& part : resolve_obj_materials(object(o, wo[i], i, arrays), wo[i] / "material"))
        b.object(std::move(part), wo[i]);
    } else {
      b.object(object(o, wo[i], i, arrays), wo[i]);
    }
  }
  if (root.contains("lights")) {
    const Where wl = top / "lights";
    array(root["lights"], wl);
    for (std::size_t i = 0; i < root["lights"].size(); ++i) b.light(delta_light(root["lights"][i], wl[i]), wl[i]);
  }
  if (root.contains("background")) {
    const json& bg = root["background"];
    if (bg.is_object() && bg.contains("environment"))
      b.environment(environment(bg, top / "background"), top / "background");
    else
      b.background(emission(bg, top / "background", false), top / "background");
  }
}

SceneDesc parse_scene(const std::string& json_text, const fs::path& path, const MeshArrays* arrays) {
  SceneBuilder b(path);
  read_scene(json_text, path, b, arrays);
  return std::move(b).build();
}

SceneDesc load_scene(const fs::path& path) {
  SceneBuilder b(path);
  load_scene(path, b);
  return std::move(b).build();
}

void load_scene(const fs::path& path, SceneBuilder& builder) {
  if (is_gltf_file(path)) return load_gltf_scene(path, builder);  // an asset as the whole scene
  read_scene(read_text_file(path), path, builder);
}

}  // namespace bouguer
