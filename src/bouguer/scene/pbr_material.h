#pragma once
// glTF's metallic-roughness material, with the extensions Bouguer reads (transmission, volume,
// ior, dispersion, emissive strength), as one of Bouguer's object roles. One job: the one mapping
// shared by the glTF reader (scene/gltf.cpp) and a scene's "pbr" objects (the Blender add-on's
// Principled BSDF), so that a glTF material and a Blender material with the same values mean the
// same surface. What each value becomes is docs/assets.md's table "Materials". Values are checked
// here, as every front end's are: the glTF reader clamps an asset's values into range first (an
// asset is someone else's file), a scene's values outside the range are refused.
#include <optional>
#include <string>

#include "bouguer/core/math.h"
#include "bouguer/scene/description.h"
#include "bouguer/scene/source.h"
#include "bouguer/scene/values.h"

namespace bouguer {

struct PbrMaterialInput {
  Vec3 base_color{1, 1, 1};  // linear Rec.709, each channel in [0, 1]
  // Read instead of base_color where given (the glTF reader's texels come multiplied by the factor).
  std::optional<TextureInput> base_color_texture;
  double metallic = 1.0, roughness = 1.0;  // each in [0, 1]; GGX α = roughness²
  std::optional<TextureInput> metallic_roughness_texture;  // G roughness, B metalness (as stored)
  Vec3 emissive{0, 0, 0};           // linear; the radiance is emissive × strength (cd/m², D65 white)
  double emissive_strength = 1.0;
  std::optional<TextureInput> emissive_texture;  // read instead of emissive where given
  double transmission = 0.0;  // in [0, 1]; above 0 the surface is a dielectric (taken as 1)
  bool thin_walled = false;   // a sheet with no inside (glTF: KHR_materials_volume thickness 0)
  double ior = 1.5;           // n_d, 1 to 5
  double dispersion = 0.0;    // KHR_materials_dispersion: 20 / V_d (0: none)
  Vec3 attenuation_color{1, 1, 1};  // the fraction kept over attenuation_distance_m, per channel
  std::optional<double> attenuation_distance_m;  // none: no absorption
};

// The role the material gives an object: exactly one of an emission, an opaque material (a
// thin sheet included), or an interface around `volume` (when the front end gives no medium of
// its own) with a GGX roughness.
struct PbrRole {
  std::optional<EmissionDesc> emission;
  std::optional<MaterialDesc> material;
  std::optional<MediumInput> volume;  // transmission through a solid: the medium it bounds
  double interface_roughness = 0.0;   // α of the interface (roughness²)
};

// `where` names the material; its keys follow the scene format's "pbr" object (docs/scene-format.md).
PbrRole pbr_role(const PbrMaterialInput& m, const Source& where);

// σ_a(λ) whose transmittance over distance_m is colour c per channel: the smooth reflectance-like
// lift of c, plus narrow Gaussians at the rgb3 lines that make it exactly c there (docs/assets.md,
// "Absorption"); a 1 nm table for a medium with unit attenuation_per_m. Each channel in (0, 1].
TableInput attenuation_sigma_a(const Vec3& colour, double distance_m);

}  // namespace bouguer
