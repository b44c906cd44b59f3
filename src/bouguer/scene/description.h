#pragma once
// The plain description a scene file parses into: values in SI units with their source
// resolved (library names, CSV files, unit conversions, the environment map read), but nothing
// built yet. `compile` (scene/compile.h) turns it into the render scene and reads no file but
// the meshes its shapes name.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "bouguer/geometry/shapes.h"
#include "bouguer/geometry/transform.h"
#include "bouguer/io/display.h"
#include "bouguer/io/texture_image.h"
#include "bouguer/lights/spot.h"
#include "bouguer/media/concentration_field.h"
#include "bouguer/media/ior.h"
#include "bouguer/media/phase.h"
#include "bouguer/lights/environment.h"
#include "bouguer/scene/texture.h"
#include "bouguer/spectra/sampled_wavelengths.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

enum class CameraType { pinhole, orthographic };
// automatic ("auto"): chosen by short trials of path, bdpt and vcm before the render
// (integrators/choose.h), the default of a scene file that names none.
enum class IntegratorType { whitted, path, light, bdpt, vcm, automatic };  // names: scene/render_modes.h

struct CameraDesc {
  CameraType type = CameraType::pinhole;
  Vec3 position_m{0, 0, 1};
  Vec3 look_at_m{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fov_deg = 40.0;    // pinhole: full angle across the shorter image side
  double width_m = 1.0;     // orthographic: extent across the shorter image side
  // Lens shift: the image window moved across the film plane, in units of the shorter image side
  // (+x right, +y up), as a view camera's or Blender's shift (its verticals stay vertical).
  double shift_x = 0.0, shift_y = 0.0;
  int width_px = 640;
  int height_px = 480;
};

struct RenderSettings {
  IntegratorType integrator = IntegratorType::whitted;
  SpectralMode spectral = SpectralMode::full;
  int spp = 16;
  int max_depth = 32;
  std::uint64_t seed = 0;
  double merge_radius_m = 0.0;  // vcm: the first iteration's merging radius (0: two pixel footprints)
  // path: next-event estimation through smooth interfaces near a dense medium's boundary
  // (integrators/events.h: ExitGuide). Unset: on where the environment map's contrast reaches
  // kExitGuideContrast (exit_guide_enabled); set: on or off as said.
  std::optional<bool> exit_guide;
  // path: next-event estimation through smooth glass (integrators/manifold.h). Off: the path
  // tracer as before it, lamps behind glass reached only by its own directions (point, spot and
  // distant lamps behind glass not at all).
  bool manifold = true;
  // path: with `manifold`, area and spherical lamps hidden by smooth faces of meshes or by an exact
  // cylinder's side reached through them (integrators/manifold.h: area_light_through_chain,
  // area_light_through_cylinder). Unset: for lamps that subtend less than kLampChainSolidAngle from
  // the nearest such glass (RenderScene: Surface::small_lamp); set: for every lamp, or none.
  std::optional<bool> area_lamp_chains;
  // path: also light paths from the point, spot and distant lamps, connected to the camera straight or
  // through smooth glass, that add what next-event estimation does not make (light reflected inside
  // glass or by a mirror before its first diffuse or scattering vertex; integrators/light.cpp,
  // docs/rendering.md: what neither makes).
  bool light_paths = false;
  // path: path guiding at diffuse surfaces (integrators/guiding.h), trained before the render; off
  // unless asked for (guiding_enabled).
  bool guiding = false;
  // path: shell transport deep in homogeneous scattering media (integrators/shell_hops.h): a walk's
  // collisions inside a sphere free of surfaces drawn at once from tables of walks. Exact; off:
  // every collision walked.
  bool shell_transport = true;
};

// An absorber whose concentration varies in space: σ_a(x, λ) = c(x)·ε(λ).
struct FieldAbsorberDesc {
  Spectrum epsilon_per_m = ConstantSpectrum{0.0};  // σ_a at concentration 1 (natural log, 1/m)
  ConcentrationField field;
};

// A scattering medium's σ_s(x, λ) = ρ(x)·σ_s(λ) and its phase function; ρ (the density) also
// scales the medium's absorption.
struct ScatteringDesc {
  Spectrum sigma_s_per_m = ConstantSpectrum{0.0};  // natural log, 1/m, at density 1
  PhaseFunction phase = IsotropicPhase{};
  std::optional<ConcentrationField> density;
  // The scatterers' own absorption (a library medium's σ_a), scaled by the density like σ_s.
  std::optional<Spectrum> sigma_a_per_m;
  // false for a library medium's `concentration` (its particles in another liquid): the density
  // then scales only the scatterers, not the medium's `absorption`.
  bool density_scales_absorption = true;
};

struct MediumDesc {
  std::string name;
  IorModel ior = ConstantIor{1.0};
  Spectrum sigma_a_per_m = ConstantSpectrum{0.0};  // natural log, 1/m, concentration applied
  bool absorbing = false;
  // Set instead of sigma_a_per_m when the medium has several absorbers or a concentration field
  // (then every absorber is here, a uniform one with a ConstantField).
  std::vector<FieldAbsorberDesc> field_absorbers;
  std::optional<ScatteringDesc> scattering;
};

// A texture image the builder has read (compile makes its MIP pyramid, scene/texture.h).
struct TextureDesc {
  std::filesystem::path file;  // for messages
  std::shared_ptr<const TextureImage> image;
  UvTransform transform;
  TextureSampler sampler;
};

// Radiance of an emitter or the background: a spectrum in the normalisation of spectra/cie.h.
struct EmissionDesc {
  Spectrum radiance = ConstantSpectrum{0.0};
  bool two_sided = false;
  std::optional<SpotProfile> spot;  // set for spot lights with a radius
  // Emitters: the radiance at a point is `radiance` times this texture's texel there, lifted as a
  // reflectance (each value in [0, 1]); see lights/light.h, AreaLight.
  std::optional<TextureDesc> texture;
};

// A diffuse reflectance: a spectrum, or a texture (its texels lifted to spectra; then `reflectance`
// is unused).
struct DiffuseDesc {
  Spectrum reflectance = ConstantSpectrum{0.5};
  std::optional<TextureDesc> reflectance_texture;
};

// A metal: complex refractive index n + ik (spectral), GGX roughness alpha (0: a mirror), or a
// texture of alpha (the mean of its channels, each in [0, 1]; then `roughness` is unused).
struct ConductorDesc {
  Spectrum n = ConstantSpectrum{0.2};
  Spectrum k = ConstantSpectrum{3.0};
  double roughness = 0.0;
  std::optional<TextureDesc> roughness_texture;
};

// glTF's metallic-roughness material (materials/surface_bsdf.h, MetallicRoughness): a base colour
// (a reflectance spectrum, or a reflectance texture read instead), a metalness and a perceptual
// roughness (GGX alpha = roughness²), the two constants or a data texture read instead (its blue
// channel the metalness, its green the roughness, glTF's layout).
struct MetallicRoughnessDesc {
  Spectrum base_colour = ConstantSpectrum{1.0};
  std::optional<TextureDesc> base_colour_texture;
  double metalness = 1.0, roughness = 1.0;
  std::optional<TextureDesc> metallic_roughness_texture;
};

// A thin dielectric sheet (materials/surface_bsdf.h, ThinDielectric): both faces' reflections summed,
// the transmitted light undeviated and tinted. `ior` is the sheet's index (constant; at a hit it is
// taken over the index of the medium around it); the tint a reflectance spectrum, or a reflectance
// texture read instead (glTF's thin-walled transmission: the base colour).
struct ThinDielectricDesc {
  double ior = 1.5;
  Spectrum tint = ConstantSpectrum{1.0};
  std::optional<TextureDesc> tint_texture;
};

using MaterialDesc = std::variant<DiffuseDesc, ConductorDesc, MetallicRoughnessDesc, ThinDielectricDesc>;

// A tangent-space normal map (scene/normal_map.h): a data texture, glTF's scale on its x and y.
struct NormalMapDesc {
  TextureDesc texture;
  double scale = 1.0;
};

struct ObjectDesc {
  std::string name;
  Shape shape;
  Transform transform;
  // Exactly one of: an interface (inside set), an emitter, a diffuse surface.
  std::optional<std::string> inside, outside, contents;
  std::optional<EmissionDesc> emission;
  std::optional<MaterialDesc> material;
  double roughness = 0.0;  // interfaces: GGX alpha of the dielectric boundary (0: smooth)
  // Interfaces: where objects with priorities overlap, the higher one's medium fills the overlap
  // (scene/nested.h). None: the object's surfaces keep the media of its two sides, as always.
  std::optional<std::int64_t> priority;  // checked by the builder: 0 to kMaxPriority
  std::optional<NormalMapDesc> normal_map;  // any surface kind; a shape with one is always meshed
};

// Lights without area (they cannot be hit, only sampled). Spectra use the normalisation of
// spectra/cie.h: a point or spot light of scale s has intensity Y = s (per steradian), a distant
// light of scale s gives irradiance Y = s on a surface facing it.
enum class DeltaLightType { point, spot, distant };

struct DeltaLightDesc {
  DeltaLightType type = DeltaLightType::point;
  Vec3 position_m{};
  Vec3 direction{0, -1, 0};  // spot: the cone axis; distant: the direction light travels
  double cone_deg = 30.0;    // spot: half-angle where the light ends
  double falloff_deg = 25.0; // spot: half-angle where the smooth falloff starts
  Spectrum intensity = ConstantSpectrum{1.0};
  double radius_m = 0.0;  // spot: > 0 makes it a disk emitter of this radius (compile.cpp)
};

struct SceneDesc {
  std::filesystem::path file;
  CameraDesc camera;
  RenderSettings render;
  std::string world_medium = "air";
  std::map<std::string, MediumDesc> media;  // predefined vacuum and air included
  std::vector<ObjectDesc> objects;
  std::vector<DeltaLightDesc> lights;
  EmissionDesc background;                     // used when there is no environment map
  std::optional<EnvironmentDesc> environment;  // "background": {"environment": "sky.exr", ...}
  std::shared_ptr<const EnvironmentMap> environment_map;  // that map, read by the builder
  // What a front end let through but changed (a glTF value clamped into what Bouguer models), one
  // line each, "file: place: what", for the command line and Python to show (SceneBuilder::warn).
  std::vector<std::string> warnings;
  DisplayDesc display;  // exposure, white balance, display curve: applied as images are written (io/display.h)
};

}  // namespace bouguer
