#include "bouguer/lights/light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "bouguer/core/frame.h"
#include "bouguer/core/warp.h"
#include "bouguer/lights/environment.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

Vec3 uniform_sphere(double u1, double u2) {
  const double z = 1.0 - 2.0 * u1, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Uniform within the cone of directions at most acos(cos_max) from +z.
Vec3 uniform_cone(double u1, double u2, double cos_max) {
  const double z = 1.0 - u1 * (1.0 - cos_max), r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// A point of the disk of the scene's bounding radius, perpendicular to w, on w's side of the
// centre: where rays from a light at infinity in direction w start.
Vec3 disk_point(const SceneBounds& b, const Vec3& w, double u1, double u2) {
  const Frame f(w);
  const double r = b.radius_m * std::sqrt(u1), phi = 2.0 * kPi * u2;
  return b.centre_m + w * b.radius_m + f.s * (r * std::cos(phi)) + f.t * (r * std::sin(phi));
}

// A point drawn uniformly over the triangle (the barycentrics of p1 and p2 from u1, u2), and its
// texture coordinates for a textured light.
struct TrianglePoint {
  Vec3 p;
  std::array<double, 2> uv{};
};
TrianglePoint triangle_point(const AreaLight& a, double u1, double u2) {
  if (u1 + u2 > 1.0) u1 = 1.0 - u1, u2 = 1.0 - u2;
  const double u0 = 1.0 - u1 - u2;
  return {a.p0 * u0 + a.p1 * u1 + a.p2 * u2,
          {a.uv[0][0] * u0 + a.uv[1][0] * u1 + a.uv[2][0] * u2, a.uv[0][1] * u0 + a.uv[1][1] * u1 + a.uv[2][1] * u2}};
}

LightLiSample li_sample(const Vec3& wi, double distance_m, double pdf, bool delta, double factor, int spectrum) {
  LightLiSample s;
  s.wi = wi;
  s.distance_m = distance_m;
  s.pdf = pdf;
  s.delta = delta;
  s.factor = factor;
  s.spectrum = spectrum;
  return s;
}

double cos_cone(const SpotProfile& s) { return std::cos(s.cone_deg * kPi / 180.0); }

// Infinite lights leave from a disk facing the scene: density of the origin per m².
double disk_pdf(const SceneBounds& b) { return 1.0 / (kPi * b.radius_m * b.radius_m); }

// The cone of directions a sphere subtends from p outside it: sin²θmax and 1 − cos θmax, the
// latter as sin²θmax / (1 + cos θmax), which does not cancel for a small cone (1 − √(1 − sin²θmax)
// loses all its digits below about 1e-8 sr; pbrt-v4 takes a Taylor term there, 2e-4 off at its
// threshold); nothing from inside or on the sphere.
struct SphereCone {
  double sin2_max = 0.0, one_minus_cos_max = 0.0;
};
std::optional<SphereCone> sphere_cone(const SphereLight& sp, const Vec3& p) {
  const Vec3 to_centre = sp.centre_m - p;
  const double dc2 = dot(to_centre, to_centre), r2 = sp.radius_m * sp.radius_m;
  if (!(dc2 > r2)) return std::nullopt;
  const double sin2_max = r2 / dc2;
  return SphereCone{sin2_max, sin2_max / (1.0 + std::sqrt(1.0 - sin2_max))};
}

double safe_sqrt(double x) { return std::sqrt(std::max(0.0, x)); }

}  // namespace

double emitted_factor(const AreaLight& light, const Vec3& direction) {
  if (!light.two_sided && dot(direction, light.normal) <= 0.0) return 0.0;
  return light.spot ? spot_falloff(*light.spot, direction) : 1.0;
}

double emitted_factor(const Light& light, const Vec3& direction, const Vec3& normal) {
  if (const auto* a = std::get_if<AreaLight>(&light)) return emitted_factor(*a, direction);
  if (std::holds_alternative<SphereLight>(light)) return dot(direction, normal) > 0.0 ? 1.0 : 0.0;
  return 0.0;
}

EmitterRadiance emitter_radiance(const Light& light) {
  if (const auto* a = std::get_if<AreaLight>(&light)) return {a->radiance, a->texture};
  if (const auto* sp = std::get_if<SphereLight>(&light)) return {sp->radiance, -1};
  return {};
}

std::optional<LightAreaSample> sample_area(const Light& light, double u1, double u2) {
  if (const auto* a = std::get_if<AreaLight>(&light)) {
    if (!(a->area_m2 > 0.0)) return std::nullopt;
    return LightAreaSample{triangle_point(*a, u1, u2).p, 1.0 / a->area_m2};
  }
  return std::nullopt;
}

std::optional<LightLiSample> sample_li(const Light& light, const Vec3& p, double u1, double u2) {
  if (const auto* a = std::get_if<AreaLight>(&light)) {
    const TrianglePoint q = triangle_point(*a, u1, u2);
    const Vec3 to = q.p - p;
    const double d = length(to);
    if (d == 0.0) return std::nullopt;
    const Vec3 wi = to / d;
    const double factor = emitted_factor(*a, -wi);
    const double cos_light = std::abs(dot(a->normal, wi));
    if (factor == 0.0 || cos_light == 0.0) return std::nullopt;
    LightLiSample s = li_sample(wi, d, d * d / (cos_light * a->area_m2), false, factor, a->radiance);
    s.texture = a->texture;
    s.uv = q.uv;
    return s;
  }
  if (const auto* sp = std::get_if<SphereLight>(&light)) {
    // A direction of the cone (θ from its axis, uniform in cos θ: 1 − cos θ = u·(1 − cos θmax),
    // and sin²θ from it without cancellation), then the point of the near cap it meets, by the
    // angle α at the centre between the direction back to p and its normal.
    const auto cone = sphere_cone(*sp, p);
    if (!cone) return std::nullopt;  // (the inside does not emit)
    const double one_minus_cos = u1 * cone->one_minus_cos_max, cos_theta = 1.0 - one_minus_cos;
    const double sin2_theta = one_minus_cos * (2.0 - one_minus_cos);
    const double cos_alpha = sin2_theta / std::sqrt(cone->sin2_max) +
                             cos_theta * safe_sqrt(1.0 - sin2_theta / cone->sin2_max);
    const double sin_alpha = safe_sqrt(1.0 - cos_alpha * cos_alpha), phi = 2.0 * kPi * u2;
    const Vec3 n = Frame(normalize(sp->centre_m - p))
                       .to_world(Vec3{-sin_alpha * std::cos(phi), -sin_alpha * std::sin(phi), -cos_alpha});
    const Vec3 to = sp->centre_m + n * sp->radius_m - p;
    const double d = length(to);
    if (!(d > 0.0)) return std::nullopt;
    return li_sample(to / d, d, 1.0 / (2.0 * kPi * cone->one_minus_cos_max), false, 1.0, sp->radiance);
  }
  if (const auto* pt = std::get_if<PointLight>(&light)) {
    const Vec3 to = pt->position_m - p;
    const double d2 = dot(to, to);
    if (d2 == 0.0) return std::nullopt;
    return li_sample(to / std::sqrt(d2), std::sqrt(d2), 1.0, true, 1.0 / d2, pt->intensity);
  }
  if (const auto* s = std::get_if<SpotLight>(&light)) {
    const Vec3 to = s->position_m - p;
    const double d2 = dot(to, to);
    if (d2 == 0.0) return std::nullopt;
    const Vec3 wi = to / std::sqrt(d2);
    const double falloff = spot_falloff(s->profile, -wi);
    if (falloff == 0.0) return std::nullopt;
    return li_sample(wi, std::sqrt(d2), 1.0, true, falloff / d2, s->intensity);
  }
  if (const auto* d = std::get_if<DistantLight>(&light))
    return li_sample(-d->direction, kInf, 1.0, true, 1.0, d->irradiance);
  if (const auto* b = std::get_if<BackgroundLight>(&light))
    return li_sample(uniform_sphere(u1, u2), kInf, 1.0 / (4.0 * kPi), false, 1.0, b->radiance);
  return sample_environment_li(std::get<EnvironmentLight>(light), u1, u2, 0.0, -1);
}

std::optional<LightLiSample> sample_environment_li(const EnvironmentLight& light, double u1, double u2, double u3,
                                                   int lobe) {
  const auto e = lobe < 0 ? light.map->sample(u1, u2) : light.map->sample(u1, u2, u3, lobe);
  if (!e) return std::nullopt;
  LightLiSample s = li_sample(e->wi, kInf, e->pdf, false, 1.0, -1);
  s.texel = e->texel;
  return s;
}

double pdf_li(const Light& light, const Vec3& p, const Vec3& wi, const Vec3& q) {
  if (const auto* a = std::get_if<AreaLight>(&light)) {
    const Vec3 to = q - p;
    const double d2 = dot(to, to), cos_light = std::abs(dot(a->normal, wi));
    return cos_light > 0.0 ? d2 / (cos_light * a->area_m2) : 0.0;
  }
  if (const auto* sp = std::get_if<SphereLight>(&light)) {  // (wi meets the sphere: q is on it)
    const auto cone = sphere_cone(*sp, p);
    return cone ? 1.0 / (2.0 * kPi * cone->one_minus_cos_max) : 0.0;
  }
  if (std::holds_alternative<BackgroundLight>(light)) return 1.0 / (4.0 * kPi);
  if (const auto* e = std::get_if<EnvironmentLight>(&light)) return e->map->pdf(wi);
  return 0.0;  // delta lights are never found by chance
}

double pdf_point(const Light& light, const Vec3& p, const Vec3& q) {
  const Vec3 to = q - p;
  const double d2 = dot(to, to);
  if (!(d2 > 0.0)) return 0.0;
  const Vec3 wi = to / std::sqrt(d2);
  if (const auto* a = std::get_if<AreaLight>(&light))
    return a->area_m2 > 0.0 && emitted_factor(*a, -wi) != 0.0 && dot(a->normal, wi) != 0.0 ? 1.0 / a->area_m2 : 0.0;
  if (const auto* sp = std::get_if<SphereLight>(&light)) {
    // The cone's directions meet the near cap only: the points whose outward normal faces p.
    const double cos_q = -dot(normalize(q - sp->centre_m), wi);
    return cos_q > 0.0 ? pdf_li(light, p, wi, q) * cos_q / d2 : 0.0;
  }
  return 0.0;
}

std::optional<LightLeSample> sample_le(const Light& light, const SceneBounds& bounds, double u1, double u2,
                                       double u3, double u4) {
  LightLeSample s;
  if (const auto* a = std::get_if<AreaLight>(&light)) {
    Vec3 n = a->normal;
    double side = 1.0;
    if (a->two_sided) {  // either side with probability ½; u3 reused within the half
      side = 0.5;
      if (u3 < 0.5) u3 *= 2.0; else u3 = 2.0 * u3 - 1.0, n = -n;
    }
    const Vec3 local = sample_cosine_hemisphere(u3, u4);
    if (local.z <= 0.0) return std::nullopt;
    const Vec3 dir = Frame(n).to_world(local);
    s.factor = emitted_factor(*a, dir);
    if (s.factor == 0.0) return std::nullopt;
    const TrianglePoint origin = triangle_point(*a, u1, u2);
    s.ray = {origin.p, dir};
    s.texture = a->texture;
    s.uv = origin.uv;
    s.normal = n;
    s.pdf_pos = 1.0 / a->area_m2;
    s.pdf_dir = side * local.z / kPi;
    s.spectrum = a->radiance;
    return s;
  }
  if (const auto* sp = std::get_if<SphereLight>(&light)) {
    const Vec3 n = uniform_sphere(u1, u2), local = sample_cosine_hemisphere(u3, u4);
    if (local.z <= 0.0) return std::nullopt;
    s.ray = {sp->centre_m + n * sp->radius_m, Frame(n).to_world(local)};
    s.normal = n;
    s.pdf_pos = 1.0 / (4.0 * kPi * sp->radius_m * sp->radius_m);
    s.pdf_dir = local.z / kPi;
    s.factor = 1.0, s.spectrum = sp->radiance;
    return s;
  }
  if (const auto* pt = std::get_if<PointLight>(&light)) {
    s.ray = {pt->position_m, uniform_sphere(u1, u2)};
    s.pdf_pos = 1.0, s.delta_position = true;
    s.pdf_dir = 1.0 / (4.0 * kPi);
    s.factor = 1.0, s.spectrum = pt->intensity;
    return s;
  }
  if (const auto* sp = std::get_if<SpotLight>(&light)) {
    const double c = cos_cone(sp->profile);
    const Vec3 dir = Frame(sp->profile.axis).to_world(uniform_cone(u1, u2, c));
    s.factor = spot_falloff(sp->profile, dir);
    if (s.factor == 0.0) return std::nullopt;
    s.ray = {sp->position_m, dir};
    s.pdf_pos = 1.0, s.delta_position = true;
    s.pdf_dir = 1.0 / (2.0 * kPi * (1.0 - c));
    s.spectrum = sp->intensity;
    return s;
  }
  if (const auto* d = std::get_if<DistantLight>(&light)) {
    s.ray = {disk_point(bounds, -d->direction, u3, u4), d->direction};
    s.pdf_pos = disk_pdf(bounds);
    s.pdf_dir = 1.0, s.delta_direction = true;
    s.factor = 1.0, s.spectrum = d->irradiance;
    return s;
  }
  Vec3 w;  // towards the light
  if (const auto* b = std::get_if<BackgroundLight>(&light)) {
    w = uniform_sphere(u1, u2);
    s.pdf_dir = 1.0 / (4.0 * kPi);
    s.spectrum = b->radiance;
  } else {
    const auto e = std::get<EnvironmentLight>(light).map->sample(u1, u2);
    if (!e) return std::nullopt;
    w = e->wi;
    s.pdf_dir = e->pdf;
    s.texel = e->texel;
  }
  s.ray = {disk_point(bounds, w, u3, u4), -w};
  s.pdf_pos = disk_pdf(bounds);
  s.factor = 1.0;
  return s;
}

LightLePdf pdf_le(const Light& light, const SceneBounds& bounds, const Vec3& direction, const Vec3& normal) {
  if (const auto* a = std::get_if<AreaLight>(&light)) {
    const double c = dot(direction, a->normal);
    if (!a->two_sided && c <= 0.0) return {1.0 / a->area_m2, 0.0};
    return {1.0 / a->area_m2, std::abs(c) / kPi * (a->two_sided ? 0.5 : 1.0)};
  }
  if (const auto* sp = std::get_if<SphereLight>(&light))
    return {1.0 / (4.0 * kPi * sp->radius_m * sp->radius_m), std::max(0.0, dot(direction, normal)) / kPi};
  if (std::holds_alternative<PointLight>(light)) return {1.0, 1.0 / (4.0 * kPi)};
  if (const auto* sp = std::get_if<SpotLight>(&light)) {
    const double c = cos_cone(sp->profile);
    return {1.0, dot(direction, sp->profile.axis) > c ? 1.0 / (2.0 * kPi * (1.0 - c)) : 0.0};
  }
  if (std::holds_alternative<DistantLight>(light)) return {disk_pdf(bounds), 1.0};
  if (std::holds_alternative<BackgroundLight>(light)) return {disk_pdf(bounds), 1.0 / (4.0 * kPi)};
  return {disk_pdf(bounds), std::get<EnvironmentLight>(light).map->pdf(-direction)};
}

double environment_power(const EnvironmentMap& map) {
  double sum = 0.0;
  for (int j = 0; j < map.height; ++j) {
    const double sin_theta = std::sin(kPi * (j + 0.5) / map.height);
    for (int i = 0; i < map.width; ++i) {
      const Vec3f& c = map.rgb[static_cast<std::size_t>(j) * static_cast<std::size_t>(map.width) + static_cast<std::size_t>(i)];
      sum += rec709_luminance(c.x, c.y, c.z) * sin_theta;
    }
  }
  return sum * (2.0 * kPi / map.width) * (kPi / map.height);
}

double spot_cosine_power(const SpotProfile& s) {
  constexpr int steps = 2048;  // midpoint rule; the smoothstep is smooth, the error is ~1e-7
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double mu = (i + 0.5) / steps;
    sum += spot_falloff(mu, s.cone_deg, s.falloff_deg) * mu;
  }
  return 2.0 * sum / steps;
}

double spot_cone_power(const SpotProfile& s) {
  constexpr int steps = 4096;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) sum += spot_falloff(-1.0 + 2.0 * (i + 0.5) / steps, s.cone_deg, s.falloff_deg);
  return 2.0 * sum / steps;
}

LightDistribution LightDistribution::by_power(const std::vector<double>& power, const std::vector<bool>& in_set) {
  LightDistribution d;
  d.pmf.assign(power.size(), 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < power.size(); ++i)
    if (in_set[i] && power[i] > 0.0) total += power[i];
  if (!(total > 0.0)) return d;
  double running = 0.0;
  for (std::size_t i = 0; i < power.size(); ++i) {
    if (!in_set[i] || !(power[i] > 0.0)) continue;
    d.lights.push_back(static_cast<int>(i));
    d.pmf[i] = power[i] / total;
    d.cdf.push_back((running += power[i]) / total);
  }
  d.cdf.back() = 1.0;
  return d;
}

std::optional<std::pair<int, double>> LightDistribution::sample(double u) const {
  if (lights.empty()) return std::nullopt;
  const auto k = static_cast<std::size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
  const int light = lights[std::min(k, lights.size() - 1)];
  return std::pair{light, pmf[static_cast<std::size_t>(light)]};
}

}  // namespace bouguer
