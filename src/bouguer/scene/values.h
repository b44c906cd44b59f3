#pragma once
// What a front end's values mean, in one place for every front end (the JSON loader, the glTF
// reader, the Python module): lengths with units, library names, RGB colours and how each use lifts them
// to a spectrum, spectrum tables and the CSV files they come in, absorption in its units and
// material files, and the assembly of a medium from its parts. A front end reads its own format
// into these plain inputs (no JSON here) and the functions below — or SceneBuilder::medium —
// turn them into the description's values in SI units, checking each and failing with one line
// that names the Source and the key below it ("scene.json: media.wine.absorption.unit: ...").
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/geometry/transform.h"
#include "bouguer/media/concentration_field.h"
#include "bouguer/media/ior.h"
#include "bouguer/media/phase.h"
#include "bouguer/scene/description.h"
#include "bouguer/scene/source.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

// ---- the inputs --------------------------------------------------------------------------------

// A length: metres, or a number with a unit ("5 mm"; nm, um, µm, mm, cm, m, km).
using LengthInput = std::variant<double, std::string>;

// A linear Rec.709 colour, lifted to a spectrum as its use requires (a reflectance, an
// illuminant, an unbounded coefficient).
struct RgbInput {
  Vec3 rgb;
};

// A tabulated spectrum: the two arrays, or a CSV file of (wavelength_nm, value) rows.
struct TableInput {
  std::vector<double> wavelength_nm, value;
  std::optional<std::filesystem::path> csv;  // set instead of the arrays
};

// A spectral quantity (a conductor's n or k, a reflectance): a constant or a table.
using SpectralInput = std::variant<double, TableInput>;

// A texture image: a file (relative to the source's folder), or an image a front end has already
// read (glTF's embedded images; `file` then only names it), with its glTF texture transform, how
// it wraps along u and v ("repeat", "clamp" or "mirror": names, checked by resolve_texture) and
// glTF's magFilter NEAREST.
struct TextureInput {
  std::string file;
  std::shared_ptr<const TextureImage> image;
  UvTransform transform;
  std::array<std::string, 2> wrap{"repeat", "repeat"};
  bool nearest_magnification = false;
};
// A texture file with the defaults: no transform, repeat, bilinear.
inline TextureInput texture_file(std::string file) {
  TextureInput t;
  t.file = std::move(file);
  return t;
}

// Radiance of an emitter, a light's intensity or the background: a named illuminant ("D65"),
// normalised to luminance Y = scale; an RGB colour (RGB (1, 1, 1) is D65 at Y = 1) times scale;
// or a table times scale (normalised to Y = scale with `normalise`); for an emitter, a texture:
// D65 at Y = scale times each texel (in [0, 1], lifted as a reflectance), so a white texel is
// (1, 1, 1) times scale.
struct EmissionInput {
  std::variant<std::string, RgbInput, TableInput, TextureInput> spectrum;
  double scale = 1.0;
  bool normalise = false;
  bool two_sided = false;
};

// A refractive index: a constant, a dispersion library entry, an Abbe number, Sellmeier or
// Cauchy coefficients, or a table.
struct IorLibraryInput {
  std::string name;
};
struct AbbeInput {
  double n_d = 1.5, V_d = 50.0;
};
using IorInput = std::variant<double, IorLibraryInput, AbbeInput, SellmeierIor, CauchyIor, TableInput>;

// A concentration or density: a number, or a field varying in space (media/concentration_field.h).
// A field's values are checked by the builder (SceneBuilder::medium), whatever front end made it.
using ConcentrationInput = std::variant<double, ConcentrationField>;

// A voxel grid as a front end names it: an OpenVDB file (relative to the source's folder), the
// grid's name, a factor on its values, and a placement applied after the grid's own index-to-world
// map.
struct GridFieldInput {
  std::string file;
  std::string grid = "density";
  double scale = 1.0;
  Transform placement;
};

// One step of an object's (or a grid's) placement, applied in order: a scale (per axis), a
// rotation by an angle about an axis, a translation in metres, or an affine matrix given by its
// four rows (the last [0, 0, 0, 1]).
struct ScaleStep {
  Vec3 factor{1, 1, 1};
};
struct RotateStep {
  double angle_deg = 0.0;
  Vec3 axis{0, 1, 0};
};
struct TranslateStep {
  Vec3 offset_m{};
};
struct MatrixStep {
  std::array<std::array<double, 4>, 4> rows{};
};
using TransformStep = std::variant<ScaleStep, RotateStep, TranslateStep, MatrixStep>;

// One absorber: a library material, a material file that names its own unit
// (scene/material_file.h), or values (a table, or RGB where only RGB data exist) in a unit
// (media/absorption.h: attenuation_per_m, absorbance_per_cm, internal_transmittance with a
// thickness, molar_absorptivity, extinction_coefficient).
struct AbsorptionLibraryInput {
  std::string name;
};
struct MaterialFileInput {
  std::filesystem::path csv;
};
struct AbsorptionValuesInput {
  std::variant<TableInput, RgbInput> values;
  std::string unit;
  std::optional<LengthInput> thickness;
};
struct AbsorptionInput {
  std::variant<AbsorptionLibraryInput, MaterialFileInput, AbsorptionValuesInput> source;
  std::optional<ConcentrationInput> concentration;  // mol/L for solutes; a factor otherwise
};

// Scattering: a library medium (its σ_s, phase, σ_a and index), optionally as a fraction of
// another liquid (`concentration`), or σ_s given as values in a unit (attenuation_per_m, _per_cm,
// _per_mm) or Rayleigh's λ⁻⁴ through one value; `density` scales σ_s (and the absorption).
struct ScatteringLibraryInput {
  std::string name;
  std::optional<ConcentrationInput> concentration;
};
struct RayleighInput {
  double at_nm = 550.0, value_per_m = 0.0;
};
struct ScatteringValuesInput {
  std::variant<TableInput, RgbInput, RayleighInput> values;
  std::string unit;  // not for Rayleigh
  PhaseFunction phase = IsotropicPhase{};
};
struct ScatteringInput {
  std::variant<ScatteringLibraryInput, ScatteringValuesInput> source;
  std::optional<ConcentrationInput> density;
};

// A medium: its index (a library absorber or scattering medium supplies a default), its
// absorbers (their σ_a add up) and its scattering. `absorption_listed`: the absorbers were given
// as a list, so messages name each by its index.
struct MediumInput {
  std::optional<IorInput> ior;
  std::vector<AbsorptionInput> absorption;
  bool absorption_listed = false;
  std::optional<ScatteringInput> scattering;
};

// A normal map: its texture and glTF's scale (a finite number).
struct NormalMapInput {
  TextureInput texture;
  double scale = 1.0;
};

// Opaque surfaces: a diffuse reflectance (a number, table, RGB or texture, 0 to 1; 0.5 when not
// given) or a conductor's n and k with a GGX roughness.
struct DiffuseInput {
  std::optional<std::variant<double, TableInput, RgbInput, TextureInput>> reflectance;
};
struct ConductorInput {
  SpectralInput n = 0.2, k = 3.0;
  double roughness = 0.0;
  std::optional<TextureInput> roughness_texture;  // read instead of `roughness`
};
// glTF's metallic-roughness (MetallicRoughnessDesc): textures are read instead of the constants.
struct MetallicRoughnessInput {
  std::variant<RgbInput, TextureInput> base_colour = RgbInput{{1.0, 1.0, 1.0}};
  double metalness = 1.0, roughness = 1.0;
  std::optional<TextureInput> metallic_roughness_texture;
};
// A thin dielectric sheet (ThinDielectricDesc): its index and the tint of what it transmits (as a
// diffuse reflectance is given; white when not given).
struct ThinDielectricInput {
  double ior = 1.5;
  std::optional<std::variant<double, TableInput, RgbInput, TextureInput>> tint;
};
using MaterialInput = std::variant<DiffuseInput, ConductorInput, MetallicRoughnessInput, ThinDielectricInput>;

// ---- what they mean ----------------------------------------------------------------------------

// "5 mm", "0.5 cm", "1.2 um", "2 m" -> metres (an Error naming the text).
double parse_length_m(const std::string& text);
// "30 deg", "0.5 rad" -> radians (an Error naming the text; a bare number has no unit and is refused).
double parse_angle_rad(const std::string& text);

// A length within the scene's extent (core/limits.h); a positive one, at least the smallest length.
double resolve_length_m(const LengthInput& length, const Source& where);
double resolve_positive_length_m(const LengthInput& length, const Source& where);

// A table, its CSV read (relative to the source's folder), non-negative unless allowed, and
// overlapping the visible range.
TabulatedSpectrum resolve_table(const TableInput& table, const Source& where, bool allow_negative = false);
Spectrum resolve_spectral(const SpectralInput& value, const Source& where);

EmissionDesc resolve_emission(const EmissionInput& emission, const Source& where);
IorModel resolve_ior(const IorInput& ior, const Source& where);
MediumDesc resolve_medium(const std::string& name, const MediumInput& medium, const Source& where);
// The image read (an Error naming the file: missing, not an image, too large) and, for a
// reflectance or data, every texel (after sRGB decoding for a reflectance) checked to lie in [0, 1];
// its wrap names checked. `where` is the texture's own place ({"texture": ..., "wrap": ...}): an
// error about the file names where / "texture", one about a wrap where / "wrap".
TextureDesc resolve_texture(const TextureInput& texture, const Source& where, TextureUse use);
// An object whose material is "mtl": its OBJ's faces split by `usemtl` into one object each (named
// "<object>: <material>"), each diffuse with its MTL's Kd or map_Kd texture (faces without a
// material: the default diffuse). Errors name the OBJ or MTL file, or the texture.
std::vector<ObjectDesc> resolve_obj_materials(const ObjectDesc& base, const Source& where);

MaterialDesc resolve_surface_material(const MaterialInput& material, const Source& where);
NormalMapDesc resolve_normal_map(const NormalMapInput& normal_map, const Source& where);

// The steps composed in order, each checked (a scale of zero, a zero rotation axis, a matrix whose
// last row is not [0, 0, 0, 1] or that is singular); `where` is the list, step i is where[i].
Transform resolve_transform(const std::vector<TransformStep>& steps, const Source& where);
// The grid read (io/vdb.h; an Error on where / "file" or where / "grid") and placed: every corner
// within the scene's extent, its index-to-world map invertible. Its scale is checked with the
// other fields' values (check_concentration_field).
GridField resolve_grid_field(const GridFieldInput& grid, const Source& where);
// A field's values, whatever front end made it: concentrations not negative, an axis of unit
// length, a positive scale length, a diffusion width within the scene's lengths, 1 to kMaxLayers
// layers with increasing bounds, a grid's scale not negative. `where` names the field; its keys
// follow the JSON schema's ("value", "layers[1][0]", ...).
void check_concentration_field(const ConcentrationField& field, const Source& where);

}  // namespace bouguer
