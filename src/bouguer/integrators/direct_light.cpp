#include "bouguer/integrators/direct_light.h"

#include <algorithm>
#include <cmath>

#include "bouguer/integrators/exit_guide.h"
#include "bouguer/integrators/manifold.h"

namespace bouguer {

double power_heuristic(double pdf_a, double pdf_b) {
  const double a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0 ? a / (a + b) : 0.0;
}

double area_light_pdf(const RenderScene& scene, const Hit& hit, const Vec3& from, const Vec3& wi) {
  const Surface& s = scene.surfaces[hit.geometry];
  const auto index = static_cast<std::size_t>(s.first_light) + hit.primitive;
  return scene.area_lights.pmf[index] * pdf_li(scene.lights[index], from, wi, hit.point);
}

double environment_pdf(const RenderScene& scene, const Vec3& d, int lobe) {
  return scene.environment ? scene.environment->pdf(d, lobe) : 0.0;
}

template <std::size_t N>
std::optional<Transmission<N>> transmission(const SceneView<N>& v, const PathVertex& from, const Vec3& wi,
                                            double distance_m, int medium, const SampledWavelengths<N>& w, Rng& rng,
                                            std::uint64_t& rays, std::span<const double> sigma_mean,
                                            bool* by_smooth_interface, Hit* blocker) {
  const RenderScene& s = v.scene;
  Transmission<N> out;
  // The ray leaves from the offset origin (offset_ray_origin) aimed at the target itself, and stops
  // short of it by 1e-4 of the way and by twice a ray's offset there (ray_offset_m), so the
  // target's own surface never blocks it. Aimed along wi from the offset origin instead, a ray
  // grazing its surface met the target's plane ε/cos θ early: 10 m from the origin, where
  // ε = 4e-5 m, a lamp 5 cm above a floor blocked its own shadow rays (the floor 13-20 % dark),
  // and a segment through a 2 mm glass wall was blocked by the wall's far face.
  const Vec3 origin = from.origin_towards(wi);
  Vec3 direction = wi;
  double remaining = distance_m, margin_m = 0.0;
  if (std::isfinite(distance_m)) {
    const Vec3 target = from.point + wi * distance_m, to = target - origin;
    remaining = length(to);
    if (remaining > 0.0) direction = to / remaining;
    margin_m = 2.0 * ray_offset_m(target);
  }
  auto t_max = [&] { return std::isinf(remaining) ? remaining : std::max(0.0, remaining * (1.0 - 1e-4) - margin_m); };
  RaySegment seg{Ray{origin, direction, t_max()}, from.point, medium,
                 from.hit ? inside_towards(s, *from.hit, from.inside, wi) : from.inside};
  // Once nothing gets through (ratio tracking's estimate can be 0 in a scattering medium), a caller
  // that asks what blocks the ray still learns it: the ray goes on without tracking. (Stopping
  // there left a lamp behind glass unlit from every vertex in a fog whose tracking had ended the
  // straight shadow ray: 12 % dark at an optical depth of 0.2.)
  bool nothing_through = false;
  auto segment = [&](const Hit* hit, const SurfaceSeen*) {
    const double length_m = hit ? length(hit->point - seg.start) : remaining;
    if (v.visibility_only) {
      // (clear as far as the geometry goes)
    } else if (const ScatteringMedium* sm = scattering_medium(s, seg.medium); sm && !nothing_through) {
      ratio_track(*sm, v.tables, Ray{seg.start, wi}, length_m, w, rng, out.tr, out.ratios);
      if (!sigma_mean.empty() && std::isfinite(length_m))
        out.tau += sigma_mean[static_cast<std::size_t>(seg.medium)] *
                   scattering_column_density(*sm, Ray{seg.start, wi}, 0.0, length_m);
    } else if (!sm && !nothing_through) {
      out.tr *= travel(v, seg.medium, Ray{seg.start, wi}, length_m, w);
    }
    if (out.tr.is_zero()) {
      if (!by_smooth_interface) return false;
      nothing_through = true;
    }
    remaining = std::max(0.0, remaining - length_m);  // (read only if it crosses here)
    seg.ray.t_max = t_max();
    return true;
  };
  const RayStop stop = advance_to_surface(s, seg, rays, segment);
  // (An infinite path through a medium that only absorbs carries nothing, at every wavelength, as
  // escaped() says, even where its σ_a is 0.)
  if (stop.at == RayStop::At::escape && nothing_through) return std::nullopt;
  if (stop.at == RayStop::At::escape)
    return std::isinf(distance_m) && absorbs(s, seg.medium) && !scattering_medium(s, seg.medium) ? std::nullopt
                                                                                                  : std::optional(out);
  if (by_smooth_interface && stop.seen)  // blocked: by a surface, or by one crossing too many
    *by_smooth_interface = smooth_glass_seen(*stop.seen);
  if (blocker && stop.hit) *blocker = *stop.hit;
  return std::nullopt;
}

namespace {

// The map's sample from its lobe (lights/light.h: sample_environment_li); a lobe takes a third
// number, from `rng` (the map's own density draws none, as before the lobes).
std::optional<LightLiSample> environment_li(const RenderScene& s, double u1, double u2, int lobe, Rng& rng) {
  const auto& light = std::get<EnvironmentLight>(s.lights[static_cast<std::size_t>(s.environment_light)]);
  return sample_environment_li(light, u1, u2, lobe >= 0 ? rng.next_double() : 0.0, lobe);
}

// Direct light at a path vertex (a surface or a point in a medium): towards(wi, pdf) gives the
// vertex's f·|cos θ| (or phase value) towards wi and the density with which the vertex itself
// would sample wi; medium_towards(wi) the medium wi leaves into.
template <std::size_t N, typename Towards, typename MediumTowards>
SampledSpectrum<N> direct_light_at(const SceneView<N>& v, const PathVertex& at, Towards towards,
                                   MediumTowards medium_towards, const SampledWavelengths<N>& w,
                                   const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays,
                                   NextEvent next_event, const ThroughInterfaces* through = nullptr,
                                   bool delta_only = false, double through_share = 1.0, bool in_sealed = false,
                                   int lobe = -1) {
  const RenderScene& s = v.scene;
  const bool mis = next_event != NextEvent::lights;
  const bool environment = next_event != NextEvent::lights && !delta_only;
  // The lamps' connections through the interfaces, made with probability through_share and
  // divided by it (dense_media.h: split_walk_nee_share). A number is drawn only where the share is
  // below 1 and there are lamps and glass (a scene lit by its map alone, or without glass, draws as
  // before); the factor is exactly 1 where nothing is thinned, so those images keep their bits.
  const bool manifold = next_event == NextEvent::lights_map_and_interfaces;
  const bool thinned = manifold && through_share < 1.0 && s.smooth_glass &&
                       !(s.delta_lights.empty() && (delta_only || s.area_lights.empty()));
  const bool interfaces = manifold && (!thinned || rng.next_double() < through_share);
  const float beyond = thinned ? static_cast<float>(1.0 / through_share) : 1.0f;
  // A strategy's mixture density over the carried wavelengths is its own density times the mean
  // of its ratios: the path's so far times the connection's own (1 without scattering media).
  auto light_ratio = [&](const Transmission<N>& t) { return mean_ratio(s, path_r_u, t.ratios.r_l); };
  auto mis_weight = [&](double light_pdf, double vertex_pdf, const Transmission<N>& t) {
    return power_heuristic(light_pdf * light_ratio(t), vertex_pdf * mean_ratio(s, path_r_u, t.ratios.r_u));
  };
  SampledSpectrum<N> sum;
  const double u_light = rng.next_double(), u1 = rng.next_double(), u2 = rng.next_double();
  const auto chosen = delta_only ? std::nullopt : s.area_lights.sample(u_light);
  // Through the casters (exact glass spheres): every delta light, and the area light drawn, at a
  // point drawn by area (manifold.h). Its own numbers, so the connections below draw as before.
  if (interfaces && !s.casters.empty()) {
    Rng side(rng.next_u32(), kManifoldStream);
    const double v1 = side.next_double(), v2 = side.next_double();
    sum += through_casters(v, at, towards, medium_towards, chosen, v1, v2, w, path_r_u, side, rays) * beyond;
  }
  if (chosen) {
    const auto& [index, p_choice] = *chosen;
    const Light& light = s.lights[static_cast<std::size_t>(index)];
    const auto li = sample_li(light, at.point, u1, u2);
    if (li && !caster_between(s, at.point, at.point + li->wi * li->distance_m)) {
      double vertex_pdf = 0.0;
      const SampledSpectrum<N> f = towards(li->wi, vertex_pdf);
      bool glass = false;
      std::optional<Transmission<N>> t;
      if (!f.is_zero())
        t = transmission(v, at, li->wi, li->distance_m, medium_towards(li->wi), w, rng, rays, {},
                         interfaces ? &glass : nullptr);
      if (t) {
        const double light_pdf = p_choice * li->pdf;
        const double weight = (mis ? mis_weight(light_pdf, vertex_pdf, *t) : 1.0) * li->factor /
                              (light_pdf * light_ratio(*t));
        sum += f * sample_radiance(v, *li, w) * t->tr * static_cast<float>(weight);
      } else if (interfaces && lamp_through_chains(v, light)) {
        // Hidden by smooth refracting faces of meshes (or turned away from the vertex, where a
        // refracted path may still reach it): on through them from the same point (manifold.h;
        // the chain's own seed finds nothing where the straight segment is clear or blocked).
        // Hidden by an exact cylinder's side: on through it, where that side is the first surface
        // the straight segment meets (which the walk can ask too).
        const Vec3 y = at.point + li->wi * li->distance_m;
        const double point_pdf = p_choice * pdf_point(light, at.point, y);
        if (glass || f.is_zero())
          sum += area_light_through_chain(v, at, light, y, point_pdf, towards, medium_towards, w, path_r_u, rng, rays) *
                 beyond;
        if (s.glass_cylinders)
          sum += area_light_through_cylinder(v, at, light, y, point_pdf, towards, medium_towards, w, path_r_u, rng,
                                             rays) *
                 beyond;
      }
    }
  }
  for (const int index : s.delta_lights) {
    const auto li = sample_li(s.lights[static_cast<std::size_t>(index)], at.point, 0.0, 0.0);
    if (!li) continue;
    const SampledSpectrum<N> radiance = v.tables.at(li->spectrum, w);
    if (li->factor == 0.0 || radiance.is_zero()) continue;
    double vertex_pdf = 0.0;
    const SampledSpectrum<N> f = towards(li->wi, vertex_pdf);
    if (f.is_zero()) continue;
    bool glass = false;
    Hit blocker;
    if (const auto t = transmission(v, at, li->wi, li->distance_m, medium_towards(li->wi), w, rng, rays, {},
                                    interfaces ? &glass : nullptr, interfaces ? &blocker : nullptr))
      sum += f * (radiance * t->tr * static_cast<float>(li->factor)) * (1.0f / light_ratio(*t));
    else if (glass)  // through the interface to the lamp (manifold.h)
      sum += delta_light_through_interface(v, at, s.lights[static_cast<std::size_t>(index)], blocker, towards,
                                           medium_towards, w, path_r_u, rng, rays) *
             beyond;
  }
  // (From inside a sealed medium the map's shadow ray always stops at its boundary: SceneMedium::
  // sealed. Its numbers are drawn all the same, so the rest of the sample is as it was.)
  if (environment && s.environment_light >= 0) {
    const double ue1 = rng.next_double(), ue2 = rng.next_double();
    const auto li = in_sealed ? std::nullopt : environment_li(s, ue1, ue2, lobe, rng);
    // Into a medium that only absorbs, the shadow ray still goes: it gets nothing where it would
    // leave the scene in the medium (an infinite path: travel gives 0), but it may leave the medium
    // through an index-matched boundary, as the walk's own direction does (skipping it lost that
    // share: a diffuse ball in an index-matched sphere of σ_a = 1e-6 per m, under the studio map,
    // was 72 % dark), or reach glass that next-event estimation through the interfaces goes on
    // through.
    const int m = li ? medium_towards(li->wi) : -1;
    if (li) {
      double vertex_pdf = 0.0;
      const SampledSpectrum<N> f = towards(li->wi, vertex_pdf);
      bool glass = false;
      if (!f.is_zero()) {
        if (const auto t = transmission(v, at, li->wi, li->distance_m, m, w, rng, rays, {}, through ? &glass : nullptr)) {
          const double weight =
              (mis ? mis_weight(li->pdf, vertex_pdf, *t) : 1.0) / (li->pdf * light_ratio(*t));
          sum += f * v.tables.environment(*s.environment, li->texel, w) * t->tr * static_cast<float>(weight);
        } else if (glass) {  // on through the smooth interfaces (exit_guide.h: surface_exit_guide)
          const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, li->wi) : at.inside;
          const SampledSpectrum<N> l = carry_to_environment(
              v, RaySegment{Ray{at.origin_towards(li->wi), li->wi}, at.point, m, inside, through->crossings},
              SampledSpectrum<N>::constant(1.0f), w, rays, through->surfaces_left, ScatteringMedia::stop);
          const Transmission<N> clear;  // (no scattering medium on the way: ratios of 1)
          if (!l.is_zero())
            sum += f * l * static_cast<float>((mis ? mis_weight(li->pdf, vertex_pdf, clear) : 1.0) /
                                              (li->pdf * light_ratio(clear)));
        }
      }
    }
  }
  return sum;
}

}  // namespace

template <std::size_t N>
SampledSpectrum<N> direct_light(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                                const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                                std::uint64_t& rays, NextEvent next_event, const ThroughInterfaces* through, int lobe) {
  auto bsdf_towards = [&](const Vec3& wi, double& bsdf_pdf) {
    bsdf_pdf = e.pdf(wo, wi);
    return e.eval(wo, wi, TransportMode::radiance);
  };
  return direct_light_at(
      v, PathVertex{hit.point, &hit, e.inside}, bsdf_towards, [&](const Vec3& wi) { return e.medium_towards(wi); }, w,
      path_r_u, rng, rays, next_event, through, false, 1.0, false, lobe);
}

namespace {

// At a scattering event: every strategy, or the delta lights' alone.
template <std::size_t N>
SampledSpectrum<N> in_medium(const SceneView<N>& v, const MediumPoint& at, const SampledWavelengths<N>& w,
                             const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays, bool through_interfaces,
                             bool delta_only, double through_share) {
  // Light arriving along −wi leaves the event along −direction, back along the camera walk.
  auto phase_towards = [&](const Vec3& wi, double& phase_pdf) {
    phase_pdf = phase_value(at.phase, -wi, -at.direction);
    return SampledSpectrum<N>::constant(static_cast<float>(phase_pdf));
  };
  return direct_light_at(
      v, PathVertex{at.x, nullptr, at.inside}, phase_towards, [&](const Vec3&) { return at.medium; }, w, path_r_u,
      rng, rays, through_interfaces ? NextEvent::lights_map_and_interfaces : NextEvent::lights_and_map_weighted,
      nullptr, delta_only, through_share, v.scene.media[static_cast<std::size_t>(at.medium)].sealed);
}

}  // namespace

template <std::size_t N>
SampledSpectrum<N> direct_light_in_medium(const SceneView<N>& v, const MediumPoint& at, const SampledWavelengths<N>& w,
                                          const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays,
                                          bool through_interfaces, double through_share) {
  return in_medium(v, at, w, path_r_u, rng, rays, through_interfaces, false, through_share);
}

template <std::size_t N>
SampledSpectrum<N> delta_lights_in_medium(const SceneView<N>& v, const MediumPoint& at, const SampledWavelengths<N>& w,
                                          const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays,
                                          bool through_interfaces, double through_share) {
  return in_medium(v, at, w, path_r_u, rng, rays, through_interfaces, true, through_share);
}

#define BOUGUER_DIRECT_LIGHT_INSTANTIATE(N) \
  template std::optional<Transmission<N>> transmission(const SceneView<N>&, const PathVertex&, const Vec3&, double, \
      int, const SampledWavelengths<N>&, Rng&, std::uint64_t&, std::span<const double>, bool*, Hit*); \
  template SampledSpectrum<N> direct_light(const SceneView<N>&, const Hit&, const SurfaceEvent<N>&, const Vec3&, \
      const SampledWavelengths<N>&, const SampledSpectrum<N>&, Rng&, std::uint64_t&, NextEvent, \
      const ThroughInterfaces*, int); \
  template SampledSpectrum<N> direct_light_in_medium(const SceneView<N>&, const MediumPoint&, \
      const SampledWavelengths<N>&, const SampledSpectrum<N>&, Rng&, std::uint64_t&, bool, double); \
  template SampledSpectrum<N> delta_lights_in_medium(const SceneView<N>&, const MediumPoint&, \
      const SampledWavelengths<N>&, const SampledSpectrum<N>&, Rng&, std::uint64_t&, bool, double);
BOUGUER_DIRECT_LIGHT_INSTANTIATE(kFullBins)
BOUGUER_DIRECT_LIGHT_INSTANTIATE(3)
BOUGUER_DIRECT_LIGHT_INSTANTIATE(kHeroCount)
#undef BOUGUER_DIRECT_LIGHT_INSTANTIATE

}  // namespace bouguer
