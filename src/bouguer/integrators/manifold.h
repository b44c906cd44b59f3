#pragma once
// Next-event estimation through one smooth planar interface (#37's manifold next-event estimation,
// its first case: Hanika, Droske, Fascione 2015, with the plane's refraction solved exactly). A
// point or spot light behind a flat refracting surface (a lamp under water, behind a pane, inside a
// glass box) sends light to a vertex in front of it along one path only, through the point y of the
// plane where Snell's law holds; no BSDF direction meets a point light, so the path tracer reached
// those paths not at all. Contract: the vertex's f·|cos θ| (or phase value) towards the arrival
// direction, times the light's intensity, the Fresnel transmittance at y, the transmittance of both
// segments (exact Bouguer–Lambert, fields and priorities as any shadow ray), and the ray tube's
// dω_light / dA⊥ at the vertex (the irradiance a point source gives through the refraction: flux is
// conserved, so no n² appears). Zero where no such path exists: the plane's solution off the face
// the straight shadow ray met, an interface that disperses or is rough, something else in the way,
// a light on the vertex's side.
#include "bouguer/integrators/direct_light.h"

namespace bouguer {

// The point of the plane through `on_plane` with unit normal `n` where a ray from x refracts
// towards p (x and p on opposite sides; eta_x, eta_p the indices on their sides): the root of
// η_x·sin θ_x = η_p·sin θ_p on the segment between their feet, which is unique (the difference of
// the two sides grows monotonically along it); solved to 1e-12 of its length. Nothing where they
// are on one side.
std::optional<Vec3> refraction_point(const Vec3& x, const Vec3& p, const Vec3& on_plane, const Vec3& n, double eta_x,
                                     double eta_p);

// The light of delta light `light` (point or spot) at vertex `at` through the smooth planar
// interface whose hit `blocker` stopped the straight shadow ray; `towards(wi, pdf)` gives the
// vertex's f·|cos θ| towards wi. Neither side's medium may scatter (the connection's spectral-MIS
// ratios are then 1).
template <std::size_t N, typename Towards>
SampledSpectrum<N> delta_light_through_plane(const SceneView<N>& v, const PathVertex& at, const Light& light,
                                             const Hit& blocker, Towards towards, const SampledWavelengths<N>& w,
                                             Rng& rng, std::uint64_t& rays) {
  const RenderScene& s = v.scene;
  Vec3 p;
  int intensity = -1;
  const SpotProfile* spot = nullptr;
  if (const auto* pt = std::get_if<PointLight>(&light)) {
    p = pt->position_m, intensity = pt->intensity;
  } else if (const auto* sp = std::get_if<SpotLight>(&light)) {
    p = sp->position_m, intensity = sp->intensity, spot = &sp->profile;
  } else {
    return {};
  }
  // A face of a mesh (an analytic surface is curved: not yet), smooth, refracting.
  if (s.rays.mesh(blocker.geometry).positions.empty()) return {};
  const Vec3 wi0 = normalize(p - at.point);
  const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, wi0) : at.inside;
  const SurfaceSeen seen = surface_seen(s, blocker, inside);
  if (seen.surface.kind != SurfaceKind::interface || seen.surface.roughness != 0.0 || seen.index_matched) return {};
  const Vec3& n = blocker.normal;
  const double side_x = dot(at.point - blocker.point, n), side_p = dot(p - blocker.point, n);
  if (!(side_x * side_p < 0.0)) return {};
  const int mx = side_x > 0.0 ? seen.medium_front : seen.medium_behind;
  const int mp = side_x > 0.0 ? seen.medium_behind : seen.medium_front;
  const SceneMedium &ax = s.media[static_cast<std::size_t>(mx)], &ap = s.media[static_cast<std::size_t>(mp)];
  if (ax.dispersive || ap.dispersive || scattering(ax.medium) || scattering(ap.medium)) return {};
  const double eta_x = ax.ior_reference, eta_p = ap.ior_reference;
  auto solve = [&](const Vec3& x) { return refraction_point(x, p, blocker.point, n, eta_x, eta_p); };
  const auto y = solve(at.point);
  if (!y) return {};
  const double dx = length(*y - at.point), dp = length(p - *y);
  if (!(dx > 0.0) || !(dp > 0.0)) return {};
  const Vec3 wi = (*y - at.point) / dx, to_light = (p - *y) / dp;
  double vertex_pdf = 0.0;
  const SampledSpectrum<N> f = towards(wi, vertex_pdf);
  if (f.is_zero()) return {};
  // The vertex to y: clear, and y on a face of the same plane (not off the face's edge).
  const auto near = transmission(v, at, wi, dx, mx, w, rng, rays);
  if (!near) return {};
  const auto face = s.rays.intersect(Ray{at.point + wi * (dx * (1.0 - 1e-4)), wi, dx * 2e-4});
  ++rays;
  if (!face || face->geometry != blocker.geometry || dot(face->normal, n) < 1.0 - 1e-9 ||
      std::abs(dot(face->point - blocker.point, n)) > 1e-6 * (dx + dp))
    return {};
  // y to the light, behind the plane.
  const auto far = transmission(v, PathVertex{face->point, &*face, inside_towards(s, *face, inside, wi)}, to_light, dp,
                                mp, w, rng, rays);
  if (!far) return {};
  const double cos_x = std::abs(dot(wi, n)), cos_p = cos_theta_transmitted(cos_x, eta_x, eta_p);
  if (!(cos_p > 0.0)) return {};
  const double transmittance = 1.0 - fresnel_dielectric(cos_x, cos_p, eta_x, eta_p);
  // The ray tube: the light's directions that reach a patch perpendicular to wi at the vertex, per
  // unit area of it, by the solve at two neighbours (the plane's mapping is smooth: central enough
  // at a step of 1e-6 of the path, whose differences keep 10 digits in double precision).
  const Frame frame(wi);
  const double step = 1e-6 * (dx + dp);
  const auto y1 = solve(at.point + frame.s * step), y2 = solve(at.point + frame.t * step);
  if (!y1 || !y2) return {};
  const Vec3 o0 = normalize(*y - p), o1 = normalize(*y1 - p), o2 = normalize(*y2 - p);
  const double tube = length(cross(o1 - o0, o2 - o0)) / (step * step);
  const double emitted = spot ? spot_falloff(*spot, o0) : 1.0;
  if (emitted == 0.0) return {};
  return f * v.tables.at(intensity, w) * near->tr * far->tr * static_cast<float>(transmittance * tube * emitted);
}

}  // namespace bouguer
