// The spectral Whitted integrator (the paper's ray tracer, done right): at each interface the
// exact unpolarised Fresnel reflectance between the two media, total internal reflection, and
// recursion into both the reflected and the refracted ray; every segment inside a medium is
// attenuated by its transmittance. Emitters are seen directly. Diffuse surfaces and rough
// conductors take direct light by shadow rays (one area light drawn by power, every delta light);
// a shadow ray that meets any other surface, glass included, is blocked (light through glass is
// the path tracer's job). Smooth conductors reflect like mirrors with their spectral Fresnel
// reflectance; thin dielectric sheets recurse into their mirror and their straight-through
// branch. Rough dielectric interfaces need the path tracer.
// A branch stops at max_depth or when its weight (the largest throughput over wavelengths from the
// camera) falls below kMinPathWeight: the light it could still add is below 1e-4 of what an
// unattenuated path would.
#include "bouguer/integrators/integrators.h"

namespace bouguer {
namespace {

constexpr float kMinPathWeight = 1e-4f;

// One camera sample's recursion: what stays the same down every branch (the scene, the
// wavelengths, the random stream, the ray count) is held here, so each recursive call passes only
// what changes and its arguments all fit in registers.
template <std::size_t N>
class WhittedTracer {
 public:
  WhittedTracer(const SceneView<N>& v, const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays,
                double cone_spread_rad)
      : v_(v), w_(w), rng_(rng), rays_(rays), cone_spread_rad_(cone_spread_rad) {}

  // Radiance along `ray`, which left the surface point `from` (the camera: its origin) in `medium`,
  // inside the nested objects `inside`; cone_width_m: the pixel's ray cone there (scene/texture.h),
  // which every branch carries on.
  SampledSpectrum<N> radiance(const Vec3& from, const Ray& ray, int medium, int depth, float weight,
                              double cone_width_m, InsideSet inside = 0);

 private:
  const SceneView<N>& v_;
  const SampledWavelengths<N>& w_;
  Rng& rng_;
  std::uint64_t& rays_;
  double cone_spread_rad_;
};

template <std::size_t N>
SampledSpectrum<N> WhittedTracer<N>::radiance(const Vec3& from, const Ray& ray, int medium, int depth, float weight,
                                              double cone_width_m, InsideSet inside) {
  const SceneView<N>& v = v_;
  const SampledWavelengths<N>& w = w_;
  ++rays_;
  const auto hit = v.scene.rays.intersect(ray);
  if (!hit) return escaped(v, medium, ray.direction, w);
  const SurfaceSeen seen = surface_seen(v.scene, *hit, inside);
  const Surface& surface = seen.surface;
  cone_width_m += cone_spread_rad_ * hit->t;
  medium = medium_arrived_through(seen, ray, *hit, medium);
  const SampledSpectrum<N> tr = travel_to(v, medium, from, ray.direction, hit->point, w);
  const Vec3 wo = -ray.direction;
  if (surface.kind == SurfaceKind::emitter) return tr * emitted(v, *hit, wo, w);
  if (surface.kind == SurfaceKind::interface && surface.roughness == 0.0) {
    // A smooth interface needs its Fresnel split only, not a BSDF in a local frame; a branch ends
    // before its direction is computed when it is too faint to follow. The reflected branch stays
    // in the medium the ray came through, the refracted one crosses to the other side.
    const float w_in = weight * tr.max_value();
    if (depth >= v.max_depth || w_in < kMinPathWeight) return {};
    // Split about the shading normal; a branch the geometric normal puts on the wrong side carries
    // nothing (surface_assembly.h, SurfaceEvent).
    const double wo_side = dot(wo, hit->normal);
    if ((dot(wo, hit->shading_normal) > 0.0) != (wo_side > 0.0)) return {};  // behind the shading normal
    const DielectricSplit d = split(interface_indices(v, seen, w), wo, hit->shading_normal);
    const auto f = static_cast<float>(d.reflectance);
    const float w_reflected = w_in * f, w_refracted = w_in * (1.0f - f);
    SampledSpectrum<N> l;
    if (w_reflected >= kMinPathWeight)
      if (const Vec3 r = d.reflected(); dot(r, hit->normal) * wo_side > 0.0)
        l = f * radiance(hit->point, {offset_ray_origin(*hit, d.from_front), r}, medium, depth + 1, w_reflected,
                         cone_width_m, inside_towards(v.scene, *hit, inside, r));
    if (f < 1.0f && w_refracted >= kMinPathWeight)
      if (const auto t = d.refracted(); t && dot(*t, hit->normal) * wo_side < 0.0) {
        const int other = d.from_front ? seen.medium_behind : seen.medium_front;
        // Radiance across the boundary: (η_o/η_t)² (materials/surface_bsdf.h). The branch weight
        // leaves it out: it judges what the branch adds once back in the camera's medium.
        const auto eta2 = static_cast<float>((d.eta_o * d.eta_o) / (d.eta_t * d.eta_t));
        l += (1.0f - f) * eta2 *
             radiance(hit->point, {offset_ray_origin(*hit, !d.from_front), *t}, other, depth + 1, w_refracted,
                      cone_width_m, inside_towards(v.scene, *hit, inside, *t));
      }
    return tr * l;
  }
  SurfaceEvent<N> e = surface_event(v, *hit, seen, wo, medium, w, cone_width_m);
  e.inside = inside;
  if (!is_specular(e.bsdf))
    return tr * direct_light(v, *hit, e, wo, w, SampledSpectrum<N>::constant(1.0f), rng_, rays_, NextEvent::lights);
  if (depth >= v.max_depth) return {};
  // A smooth conductor: a mirror with its spectral Fresnel reflectance. A thin sheet: its mirror
  // branch (R') and its undeviated one (T' times the tint), both followed, each weighted by the
  // probability with which sample() draws it.
  const auto* sheet = std::get_if<ThinDielectric<N>>(&e.bsdf);
  const double r = sheet ? thin_dielectric_reflectance(std::abs(dot(wo, e.frame.n)), sheet->eta) : 1.0;
  SampledSpectrum<N> l;
  for (const auto& [uc, share] : {std::pair{0.0, r}, std::pair{1.0, 1.0 - r}}) {
    if (!(share > 0.0)) continue;
    const auto s = e.sample(wo, uc, 0.0, 0.0, TransportMode::radiance);
    if (!s) continue;
    const SampledSpectrum<N> f = s->weight * static_cast<float>(share);
    const float w_branch = weight * (tr * f).max_value();
    if (w_branch < kMinPathWeight) continue;
    l += tr * f * radiance(hit->point, {offset_ray_origin(*hit, s->wi), s->wi}, e.medium_towards(s->wi), depth + 1,
                           w_branch, cone_width_m, inside);
  }
  return l;
}

}  // namespace

void render_whitted(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                    SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    // Whitted keeps every carried wavelength (no dispersion_u).
    render_camera_paths<N, false>(scene, settings, film, region, range, control, stats,
                           [](const SceneView<N>& v, const Ray& ray, SampledWavelengths<N>& w, double, Rng& rng,
                              std::uint64_t& rays) {
                             const Camera::Cone cone = v.camera.pixel_cone();
                             return WhittedTracer<N>(v, w, rng, rays, cone.spread_rad)
                                 .radiance(ray.origin, ray, v.scene.world_medium, 0, 1.0f, cone.width_m);
                           });
  });
}

}  // namespace bouguer
