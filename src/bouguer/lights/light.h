#pragma once
// Lights as a closed set: area emitters (one per triangle), emitting spheres, point, spot and
// distant lights, a constant background and an environment map, each a small plain struct with
// the same verbs.
// Spectra are ids into the scene's spectral tables: a light sample returns the id and a scalar
// factor on it, so lights hold nothing per spectral mode. Radiance and intensity spectra use the
// normalisation of spectra/cie.h.
//
//   sample_li(light, p, u):  a direction from p towards the light, its distance (infinite for
//       distant and infinite lights), the factor on the light's spectrum that gives the incident
//       radiance (delta lights: radiance × solid angle, i.e. intensity × falloff / d²), and the
//       solid-angle density of this light's own sampling (delta lights: 1, flagged delta).
//   pdf_li(light, p, wi, q): that density for a direction found otherwise (q: the point hit on an
//       area light).
//   sample_le(light, bounds, u): a ray leaving the light, the densities of its origin (per m²)
//       and direction (per sr), 1 for a delta in either, and the factor on the spectrum.
//   emitted_factor(light, direction, normal): the factor on a surface emitter's radiance (an area
//       light or a sphere) leaving a point with outward normal `normal` in `direction`.
//   power(light, ...): emitted flux as luminance (lm-like units of the normalisation), for
//       choosing lights in proportion to what they give.
#include <array>
#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/geometry/ray_scene.h"
#include "bouguer/lights/spot.h"

namespace bouguer {

struct EnvironmentMap;

// A textured emitter's radiance at a point is its spectrum times texture `texture`'s lifted texel
// at the point's UV (the scene's texture table; integrators/events.h reads it). Its points are still
// drawn uniformly by area, so every density (pdf_li, sample_le, pdf_le) is the untextured one and
// the radiance read at the drawn point is exact; only the choice between lights by power uses the
// texture's mean over the triangle (`texture_mean`, its luminance as a factor).
struct AreaLight {
  std::uint32_t geometry = 0, primitive = 0;
  Vec3 p0, p1, p2;
  Vec3 normal;  // unit, the emitting side (both when two_sided)
  double area_m2 = 0.0;
  int radiance = -1;  // spectrum id
  bool two_sided = false;
  std::optional<SpotProfile> spot;  // spot lights with a radius: the angular profile
  int texture = -1;                             // -1: none
  std::array<std::array<double, 2>, 3> uv{};    // the corners' texture coordinates
  double texture_mean = 1.0;                    // > 0
};

// An emitting sphere (analytic, not tessellated), radiating outward only with the radiance
// `radiance`, uniform over its surface. Seen from outside it is sampled by the cone of directions
// it subtends (pbrt-v4's Sphere::Sample: every direction of the cone meets it, and none of the
// points that face away is drawn); its light paths leave from a point drawn uniformly by area,
// cosine-distributed about the normal.
struct SphereLight {
  std::uint32_t geometry = 0;
  Vec3 centre_m;
  double radius_m = 0.0;
  int radiance = -1;  // spectrum id
};

struct PointLight {
  Vec3 position_m;
  int intensity = -1;
};

struct SpotLight {
  Vec3 position_m;
  SpotProfile profile;
  int intensity = -1;
};

// Light arriving from one direction with irradiance `irradiance` on a surface facing it.
struct DistantLight {
  Vec3 direction;  // the direction light travels
  int irradiance = -1;
};

// Constant radiance from every direction not blocked by the scene.
struct BackgroundLight {
  int radiance = -1;
};

struct EnvironmentLight {
  const EnvironmentMap* map = nullptr;
};

using Light = std::variant<AreaLight, SphereLight, PointLight, SpotLight, DistantLight, BackgroundLight, EnvironmentLight>;

// Whether a light is a surface that rays meet (an area light or a sphere: SurfaceKind::emitter).
inline bool on_a_surface(const Light& light) {
  return std::holds_alternative<AreaLight>(light) || std::holds_alternative<SphereLight>(light);
}

// A sphere that holds every surface: where lights at infinity start their rays.
struct SceneBounds {
  Vec3 centre_m;
  double radius_m = 1.0;
};

struct LightLiSample {
  Vec3 wi;
  double distance_m = 0.0;
  double pdf = 0.0;
  bool delta = false;
  double factor = 0.0;
  int spectrum = -1;  // -1 with texel >= 0: the environment map's texel
  int texel = -1;
  int texture = -1;  // a textured area light: its texture, read at uv (AreaLight)
  std::array<double, 2> uv{};
};

struct LightLeSample {
  Ray ray;
  Vec3 normal;            // area lights: the emitting side's normal; else zero
  double pdf_pos = 0.0;   // per m² (1 for a delta position)
  double pdf_dir = 0.0;   // per sr (1 for a delta direction)
  bool delta_position = false, delta_direction = false;
  double factor = 0.0;
  int spectrum = -1;
  int texel = -1;
  int texture = -1;  // as in LightLiSample
  std::array<double, 2> uv{};
};

std::optional<LightLiSample> sample_li(const Light& light, const Vec3& p, double u1, double u2);
// The map's sample from its lobe `lobe` (lights/environment.h: the map times about a surface's
// cosine; u3 places the row and the texel) or, with lobe < 0, from its own density, as sample_li
// draws it (u3 unused). The path tracer's next-event estimation at a surface draws from a lobe.
std::optional<LightLiSample> sample_environment_li(const EnvironmentLight& light, double u1, double u2, double u3,
                                                   int lobe);
// A point drawn uniformly by area on an area light's triangle, for connections that reach it
// along a path other than the straight line (integrators/manifold.h, which draws on a spherical
// lamp's facing cap itself): the point and the density per m². Nothing for other lights.
struct LightAreaSample {
  Vec3 p;
  double pdf_area = 0.0;
};
std::optional<LightAreaSample> sample_area(const Light& light, double u1, double u2);
double pdf_li(const Light& light, const Vec3& p, const Vec3& wi, const Vec3& q);
// The density per m² with which sample_li from p draws the point q of an area light or an emitting
// sphere (0 where it never draws it: behind a one-sided area light, a sphere's far side or from
// inside it). Next-event estimation through a chain of refractions (integrators/manifold.h) goes on
// from the point drawn for the straight line, and the walks weigh themselves against it with this.
double pdf_point(const Light& light, const Vec3& p, const Vec3& q);
std::optional<LightLeSample> sample_le(const Light& light, const SceneBounds& bounds, double u1, double u2,
                                       double u3, double u4);
// The densities with which sample_le draws a ray leaving `light` in `direction` (area lights and
// spheres: from a point of theirs whose outward normal is `normal`; lights at infinity:
// `direction` the one light travels, the origin any point of the disk): of the origin (per m², 1
// for a delta) and of the direction (per sr, 1 for a delta). The bidirectional estimators weigh
// their strategies with these.
struct LightLePdf {
  double pos = 0.0, dir = 0.0;
};
LightLePdf pdf_le(const Light& light, const SceneBounds& bounds, const Vec3& direction, const Vec3& normal = {});

// `luminance` gives the luminance of a spectrum id (the scene's tables know them).
template <typename Luminance>
double power(const Light& light, const SceneBounds& bounds, Luminance luminance);

// The factor on an area light's radiance for light leaving in `direction` (1 but for spot disks;
// 0 behind a one-sided emitter).
double emitted_factor(const AreaLight& light, const Vec3& direction);
// The same for a surface emitter (on_a_surface) at a point with outward normal `normal` (a
// sphere: 1 outward, 0 inward); 0 for any other light.
double emitted_factor(const Light& light, const Vec3& direction, const Vec3& normal);
// A surface emitter's radiance spectrum id and emission texture (-1: none).
struct EmitterRadiance {
  int spectrum = -1, texture = -1;
};
EmitterRadiance emitter_radiance(const Light& light);

// Lights drawn in proportion to their power (a CDF, searched by bisection): the pmf of each of
// the scene's lights (0 for lights outside the set) and a draw.
struct LightDistribution {
  std::vector<int> lights;    // scene light indices in the set
  std::vector<double> cdf;    // cumulative power fractions, last = 1
  std::vector<double> pmf;    // by scene light index

  static LightDistribution by_power(const std::vector<double>& power, const std::vector<bool>& in_set);
  bool empty() const { return lights.empty(); }
  // A scene light index and its probability; nullopt when the set is empty.
  std::optional<std::pair<int, double>> sample(double u) const;
};

// ---- inline ------------------------------------------------------------------------------------

double environment_power(const EnvironmentMap& map);  // ∫ luminance dω over the sphere
double spot_cosine_power(const SpotProfile& s);       // 2∫ falloff(μ) μ dμ over [0, 1]
double spot_cone_power(const SpotProfile& s);         // ∫ falloff(μ) dμ over [−1, 1]

template <typename Luminance>
double power(const Light& light, const SceneBounds& bounds, Luminance luminance) {
  constexpr double pi = 3.14159265358979323846;
  const double disk = pi * bounds.radius_m * bounds.radius_m;
  if (const auto* a = std::get_if<AreaLight>(&light))
    return pi * a->area_m2 * luminance(a->radiance) * a->texture_mean * (a->two_sided ? 2.0 : 1.0) *
           (a->spot ? spot_cosine_power(*a->spot) : 1.0);
  if (const auto* sp = std::get_if<SphereLight>(&light))
    return pi * 4.0 * pi * sp->radius_m * sp->radius_m * luminance(sp->radiance);
  if (const auto* p = std::get_if<PointLight>(&light)) return 4.0 * pi * luminance(p->intensity);
  if (const auto* s = std::get_if<SpotLight>(&light)) return 2.0 * pi * luminance(s->intensity) * spot_cone_power(s->profile);
  if (const auto* d = std::get_if<DistantLight>(&light)) return disk * luminance(d->irradiance);
  if (const auto* b = std::get_if<BackgroundLight>(&light)) return 4.0 * pi * disk * luminance(b->radiance);
  return disk * environment_power(*std::get<EnvironmentLight>(light).map);
}

}  // namespace bouguer
