#include "bouguer/integrators/splats.h"

#include <cmath>

#include "bouguer/integrators/manifold.h"

namespace bouguer {

namespace {

// A light-path vertex's paths to the pinhole through smooth glass: where a smooth refracting
// interface stops the straight segment (`blocker`), and through every caster (an exact glass
// ball), the paths on which each crossing refracts, solved as the path tracer solves them to a
// point lamp (manifold.h) with the pinhole for the lamp, each splatted where its last direction
// lands on the film. A path's value is the vertex's f·|cos θ| towards its first crossing, Fresnel
// at each crossing, every segment's transmittance and the forward ray tube dω_camera/dA⊥_x traced
// from the pinhole (TubeFrom::point), times the camera's We·cos θ_camera and (η_camera/η_x)²: the
// film measures radiance at the lens, and a camera ray carries radiance across the crossings
// scaled by the squared ratio of the indices (radiance mode; the light path's own weights are
// importance mode's, without it). No other strategy of the light tracer makes these paths (a
// connection to a pinhole is its only way to the camera), so they are not weighted (nor in bdpt,
// which asks for them only where no other strategy of its makes them:
// Bdpt::through_glass_to_camera). Only the
// pinhole: an orthographic camera's direction is a delta, and its paths would need the film
// point solved too.
template <std::size_t N, typename Towards, typename MediumTowards>
void splat_through_glass(const SceneView<N>& v, const PathVertex& at, const Hit* blocker, Towards towards,
                         MediumTowards medium_towards, const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w,
                         const SampledSpectrum<N>& path_r_u, Rng& rng, FilmBuffer& film, std::uint64_t& rays) {
  const RenderScene& s = v.scene;
  const Camera& camera = v.camera;
  if (!v.manifold || !s.smooth_glass || camera.desc.type != CameraType::pinhole || (!blocker && s.casters.empty()))
    return;
  const Vec3 q = camera.desc.position_m;
  // (Its own generator, seeded from the walk's: however many numbers the paths take, the walk's
  // stay where they were.)
  Rng side(rng.next_u32(), kManifoldStream);
  auto end = [&](const manifold_detail::Reach<N>& r) {
    return manifold_detail::point_end(v, SampledSpectrum<N>::constant(1.0f), r, w, side, rays);
  };
  auto add = [&](const SampledSpectrum<N>& l, const manifold_detail::Reach<N>& r) {
    const Vec3 d = -r.to_light;  // the camera ray's direction
    const double we = camera.we(Ray{q, d});
    const auto xy = camera.film_position(q + d);
    if (!(we > 0.0) || !xy) return;
    const double eta = s.media[static_cast<std::size_t>(r.medium)].ior_reference /
                       s.media[static_cast<std::size_t>(medium_towards(r.wi))].ior_reference;
    add_splat(film, v.tables, w, (*xy)[0], (*xy)[1],
              beta * l * static_cast<float>(we * dot(d, camera.forward) * eta * eta));
  };
  if (blocker)
    through_interface_each(v, at, q, *blocker, towards, medium_towards, w, path_r_u, side, rays, TubeFrom::point, end,
                           add);
  const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, normalize(q - at.point)) : at.inside;
  for (const ManifoldCaster& c : s.casters)
    manifold_detail::through_each(v, at, inside, manifold_detail::caster_interface(s, c), q, towards, medium_towards,
                                  w, path_r_u, side, rays, end, add);
}

// Adds `value` (already multiplied by everything but the connection and the camera's factor) at
// the camera's film position when the straight connection gets through; the light tracer has no
// other strategy for it, so only its own ratios divide it. Where a smooth refracting interface
// stops it, or where casters are, the paths through the glass (splat_through_glass): `towards`
// and `medium_towards` as next-event estimation's (manifold.h). CameraPaths::through_glass: those
// alone (bdpt, whose own connection is the straight one).
template <std::size_t N, typename Towards, typename MediumTowards>
void splat_towards(const SceneView<N>& v, const PathVertex& at, Towards towards, MediumTowards medium_towards,
                   const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u,
                   Rng& rng, FilmBuffer& film, std::uint64_t& rays, CameraPaths which) {
  bool glass = false;
  Hit blocker;
  const auto c = which == CameraPaths::all ? v.camera.connect(at.point) : std::nullopt;
  double pdf = 0.0;
  const SampledSpectrum<N> value = c ? beta * towards(c->wi, pdf) : SampledSpectrum<N>{};
  if (!value.is_zero()) {
    const auto t = transmission(v, at, c->wi, c->distance_m, medium_towards(c->wi), w, rng, rays, {}, &glass, &blocker);
    if (t)
      add_splat(film, v.tables, w, c->film_x, c->film_y,
                value * t->tr * static_cast<float>(c->factor / mean_ratio(v.scene, path_r_u, t->ratios.r_l)));
  } else if (v.manifold && v.scene.smooth_glass && v.camera.desc.type == CameraType::pinhole) {
    // (Outside the image, or not sent that way, or not asked for, the straight segment may still be
    // glass the camera sees it through: what stops it seeds the solve. A geometric question: it
    // draws nothing.)
    const Vec3 q = v.camera.desc.position_m;
    const InsideSet inside = at.hit ? inside_towards(v.scene, *at.hit, at.inside, normalize(q - at.point)) : at.inside;
    const auto first = first_surface(v.scene, at.point, at.hit, inside, q, rays);
    if (first && smooth_glass_seen(first->seen)) glass = true, blocker = first->hit;
  }
  splat_through_glass(v, at, glass ? &blocker : nullptr, towards, medium_towards, beta, w, path_r_u, rng, film, rays);
}

}  // namespace

template <std::size_t N>
void splat_surface_to_camera(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                             const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w,
                             const SampledSpectrum<N>& path_r_u, Rng& rng, FilmBuffer& film, std::uint64_t& rays,
                             CameraPaths which) {
  auto towards = [&](const Vec3& wi, double& pdf) {
    pdf = e.pdf(wo, wi);
    return e.eval(wo, wi, TransportMode::importance);
  };
  auto medium_towards = [&](const Vec3& wi) { return e.medium_towards(wi); };
  splat_towards(v, PathVertex{hit.point, &hit, e.inside}, towards, medium_towards, beta, w, path_r_u, rng, film, rays,
                which);
}

template <std::size_t N>
void splat_medium_to_camera(const SceneView<N>& v, const MediumPoint& at, const SampledSpectrum<N>& beta,
                            const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                            FilmBuffer& film, std::uint64_t& rays, CameraPaths which) {
  auto towards = [&](const Vec3& wi, double& pdf) {
    pdf = phase_value(at.phase, at.direction, wi);
    return SampledSpectrum<N>::constant(static_cast<float>(pdf));
  };
  auto medium_towards = [&](const Vec3&) { return at.medium; };
  splat_towards(v, PathVertex{at.x, nullptr, at.inside}, towards, medium_towards, beta, w, path_r_u, rng, film, rays,
                which);
}

template <std::size_t N>
void splat_light_to_camera(const SceneView<N>& v, const Hit& at, const Light& light, int medium,
                           const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w, Rng& rng,
                           FilmBuffer& film, std::uint64_t& rays) {
  auto towards = [&](const Vec3& wi, double& pdf) {
    pdf = 0.0;
    return SampledSpectrum<N>::constant(static_cast<float>(emitted_factor(light, wi, at.normal) *
                                                           std::abs(dot(wi, at.normal))));
  };
  auto medium_towards = [&](const Vec3&) { return medium; };
  splat_towards(v, PathVertex{at.point, &at}, towards, medium_towards, beta, w, SampledSpectrum<N>::constant(1.0f),
                rng, film, rays, CameraPaths::all);
}

#define BOUGUER_SPLATS_INSTANTIATE(N) \
  template void splat_surface_to_camera(const SceneView<N>&, const Hit&, const SurfaceEvent<N>&, const Vec3&, \
      const SampledSpectrum<N>&, const SampledWavelengths<N>&, const SampledSpectrum<N>&, Rng&, FilmBuffer&, \
      std::uint64_t&, CameraPaths); \
  template void splat_medium_to_camera(const SceneView<N>&, const MediumPoint&, const SampledSpectrum<N>&, \
      const SampledWavelengths<N>&, const SampledSpectrum<N>&, Rng&, FilmBuffer&, std::uint64_t&, CameraPaths); \
  template void splat_light_to_camera(const SceneView<N>&, const Hit&, const Light&, int, \
      const SampledSpectrum<N>&, const SampledWavelengths<N>&, Rng&, FilmBuffer&, std::uint64_t&);
BOUGUER_SPLATS_INSTANTIATE(kFullBins)
BOUGUER_SPLATS_INSTANTIATE(3)
BOUGUER_SPLATS_INSTANTIATE(kHeroCount)
#undef BOUGUER_SPLATS_INSTANTIATE

}  // namespace bouguer
