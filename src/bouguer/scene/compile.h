#pragma once
// compile: SceneDesc -> RenderScene, the immutable scene every estimator reads. Shapes become
// triangles or analytic surfaces in one RayScene; every geometry id maps to a Surface that says
// what it is and which media lie on its two sides; every spectrum becomes an id into `spectra`,
// which a render turns into flat tables for its spectral mode (scene/spectral_tables.h). Nothing here is looked up
// by name during rendering, and nothing changes a compiled scene during a render (between renders
// scene/update.h may rewrite spectra, the light powers or the camera): render settings are separate.
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "bouguer/geometry/ray_scene.h"
#include "bouguer/lights/light.h"
#include "bouguer/materials/bsdf.h"
#include "bouguer/media/medium.h"
#include "bouguer/scene/spectral_tables.h"
#include "bouguer/scene/description.h"
#include "bouguer/scene/nested.h"

namespace bouguer {

enum class SurfaceKind { interface, emitter, opaque };

struct Surface {
  SurfaceKind kind = SurfaceKind::interface;
  int medium_behind = -1;  // index into RenderScene::media, on the side opposite the normal
  int medium_front = -1;   // on the side the normal points to
  int material = -1;       // opaque surfaces: index into materials
  int first_light = -1;    // emitters: the area light of primitive p is lights[first_light + p]
  // Emitters: whether they subtend less than kLampChainSolidAngle seen from the nearest smooth
  // refracting mesh or exact cylinder, where next-event estimation goes on to
  // them through chains of mesh faces and cylinders' sides unless the render says otherwise
  // (integrators/manifold.h: area_light_through_chain, area_light_through_cylinder;
  // RenderSettings::area_lamp_chains).
  bool small_lamp = false;
  double roughness = 0.0;  // interfaces: GGX alpha (0: smooth)
  int albedo = -1;         // rough interfaces: index into RenderScene::dielectric_albedo
  // A smooth interface between two media of the same index: it neither reflects nor refracts, so
  // light crosses it unchanged and shadow rays pass through it (a medium boundary only).
  bool index_matched = false;
  // A surface of an object with a priority: its index k in RenderScene::nested. Its media are
  // then the path's (scene/nested.h), medium_front and medium_behind the ones it has alone.
  int nested = -1;
  // A normal map: an id into RenderScene::textures and glTF's scale (scene/normal_map.h); -1: none.
  int normal_map = -1;
  double normal_scale = 1.0;
  std::string object;      // for messages
};

// Opaque surfaces (two-sided): spectra are ids into RenderScene::spectra.
struct DiffuseMaterial {
  int reflectance = -1;
  int reflectance_texture = -1;  // an id into RenderScene::textures, read instead when set
};
struct ConductorMaterial {
  int n = -1, k = -1;
  double alpha = 0.0;
  int alpha_texture = -1;  // read instead when set: alpha is the mean of its texel's channels
};
// glTF's metallic-roughness (MetallicRoughnessDesc); each texture read instead of its constants.
struct MetallicRoughnessMaterial {
  int base_colour = -1, base_colour_texture = -1;
  double metalness = 1.0, roughness = 1.0;
  int metallic_roughness_texture = -1;  // B: metalness, G: roughness
};
// A thin dielectric sheet (ThinDielectricDesc): its index over vacuum, its tint.
struct ThinDielectricMaterial {
  double ior = 1.5;
  int tint = -1, tint_texture = -1;
};
using SurfaceMaterial = std::variant<DiffuseMaterial, ConductorMaterial, MetallicRoughnessMaterial, ThinDielectricMaterial>;

// An exact sphere of smooth glass (or liquid) that next-event estimation reaches lights through
// (integrators/manifold.h): a smooth, refracting, non-dispersive interface of an object without a
// priority (its media are its own), placed by a similarity transform.
struct ManifoldCaster {
  std::uint32_t geometry = 0;
  Vec3 centre_m;
  double radius_m = 0.0;
  // Whether connections cross it twice (in and out again): not where its inside scatters, whose
  // light mostly does not get across (its scattering events connect once instead), and which
  // would cost a solve at every vertex around it for little.
  bool twice = true;
};

struct RenderScene {
  std::filesystem::path file;
  CameraDesc camera;
  RayScene rays;
  std::vector<Surface> surfaces;  // by geometry id
  std::vector<SceneSpectrum> spectra;
  std::vector<SceneMedium> media;
  int world_medium = 0;
  bool dispersive = false;  // whether any medium's index varies with wavelength
  bool scatters = false;    // whether any medium scatters (the estimators then track it)
  std::vector<NestedObject> nested;  // the objects with a priority, by priority (scene/nested.h)
  std::vector<SurfaceMaterial> materials;
  TextureTable textures;
  std::shared_ptr<const EnvironmentMap> environment;  // lights point to it: kept at one address
  std::vector<Light> lights;
  std::vector<double> light_power;  // by light, luminance flux (lights/light.h)
  // Next-event estimation draws one area light by power; every delta light and the environment
  // map are sampled at each event. Light paths start at any light, drawn by power.
  LightDistribution area_lights, emitters;
  LightDistribution delta_lamps;  // the point, spot and distant lamps by power (the path tracer's light paths)
  std::vector<int> delta_lights;
  int environment_light = -1;
  int background_light = -1;  // the constant background (zero when an environment map is set)
  SceneBounds bounds;
  // Energy compensation of rough interfaces, tabulated with the two media's indices at
  // kReferenceWavelengthNm (the albedo varies by well under 1 % over a glass's dispersion).
  std::vector<DielectricAlbedo> dielectric_albedo;
  std::vector<ManifoldCaster> casters;  // at most kMaxCasters, in geometry order
  bool small_lamps = false;  // whether any emitter's Surface::small_lamp is set
  // Whether any exact cylinder's side is smooth glass that next-event estimation refracts
  // through to area lamps (manifold.h: area_light_through_cylinder).
  bool glass_cylinders = false;
  // Whether any surface is a smooth interface between media of different indices (the light
  // tracer looks for a connection through glass only then: integrators/splats.cpp).
  bool smooth_glass = false;
};
// Unless the scene says otherwise (RenderSettings::area_lamp_chains), an area or spherical lamp is
// reached through chains of mesh faces and exact cylinders' sides where it subtends less than this
// seen from the nearest such glass (a disk about 14° across: Surface::small_lamp): a larger lamp is found often enough by
// the walk's own refracted directions that a chain at every vertex costs more than it saves
// (docs/performance.md: sunset-in-a-tank's panel 3.6 times the time for 8 % less error).
inline constexpr double kLampChainSolidAngle = 0.05;  // sr
inline constexpr std::size_t kMaxCasters = 8;

// The caster whose surface is `geometry`, or null.
inline const ManifoldCaster* find_caster(const RenderScene& s, std::uint32_t geometry) {
  for (const ManifoldCaster& c : s.casters)
    if (c.geometry == geometry) return &c;
  return nullptr;
}

// The steps, in order: lower the media (predefined ones included), tessellate each object
// (spot lights with a radius as disk emitters) within the memory available, or keep it analytic
// (spheres, cylinders and disks that are not emitters), check that meshed interfaces are closed, add each part to the ray scene with its surface, add the delta lights
// and the environment map or background, and the light distributions by power. Reads no file
// but the mesh files that shapes name; the environment map comes read in `desc`.
RenderScene compile(const SceneDesc& desc);

// Whether an interface between media a and b neither reflects nor refracts: the same medium, or
// two of the same index at every wavelength.
bool indices_match(const RenderScene& s, int a, int b);

}  // namespace bouguer
