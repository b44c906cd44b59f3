#include "bouguer/integrators/walk.h"

#include <cmath>

namespace bouguer {
namespace {

// σ̄_s·∫ρ dt over [0, t] from `start` along d in `medium` (0 where it does not scatter).
template <std::size_t N>
double scattering_depth(const SceneView<N>& v, const WalkMedia& media, int medium, const Vec3& start, const Vec3& d,
                        double t) {
  const double sigma = media.sigma(medium);
  if (!(sigma > 0.0)) return 0.0;
  return sigma * column_density(scattering_medium(v.scene, medium)->density, start, d, 0.0, t);
}

template <std::size_t N>
Vertex<N> next_vertex(VertexKind kind, const Vec3& point, const WalkState<N>& state, double tau) {
  Vertex<N> x;
  x.kind = kind;
  x.point = point;
  x.wo = -state.ray.direction;
  x.tau_in = tau;
  x.beta = state.beta;
  x.r_u = state.mis.r_u;
  return x;
}

}  // namespace

template <std::size_t N>
void random_walk(const SceneView<N>& v, const WalkMedia& media, TransportMode mode, WalkState<N>& state,
                 std::size_t max_vertices, const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays,
                 std::vector<Vertex<N>>& path) {
  const RenderScene& scene = v.scene;
  double tau = 0.0;  // along the segment from the last vertex, across index-matched boundaries
  auto record = [&](Vertex<N>&& x) {
    x.pdf_fwd = to_area_density(state.pdf_dir, path.back().point, x, tau, state.parallel);
    path.push_back(std::move(x));
  };
  // The previous vertex as the new one would sample it, with solid-angle density pdf_dir.
  auto set_reverse = [&](double pdf_dir) {
    Vertex<N>& at = path.back();
    Vertex<N>& prev = path[path.size() - 2];
    prev.pdf_rev = to_area_density(pdf_dir, at.point, prev, at.tau_in);
  };
  while (path.size() < max_vertices) {
    ++rays;
    const auto hit = scene.rays.intersect(state.ray);
    if (!hit) {  // a camera subpath may end on a light at infinity
      const int light = scene.environment_light >= 0 ? scene.environment_light : scene.background_light;
      if (mode == TransportMode::radiance && light >= 0 && !absorbs(scene, state.medium) &&
          !scattering_medium(scene, state.medium)) {
        Vertex<N> x = next_vertex(VertexKind::light, Vec3{}, state, tau);
        x.infinite = true;
        x.light = light;
        x.light_dir = state.ray.direction;
        x.pdf_fwd = state.pdf_dir * std::exp(-tau);
        path.push_back(std::move(x));
      }
      return;
    }
    const Surface& surface = scene.surfaces[hit->geometry];
    state.medium = medium_arrived_through(surface, state.ray, *hit, state.medium);
    const Vec3 d = state.ray.direction;
    if (const auto x = through_medium(v, state.medium, state.start, d, *hit, w, rng, state.beta, state.mis)) {
      tau += scattering_depth(v, media, state.medium, state.start, d, length(*x - state.start));
      if (state.beta.is_zero()) return;
      const ScatteringMedium& sm = *scattering_medium(scene, state.medium);
      Vertex<N> vx = next_vertex(VertexKind::medium, *x, state, tau);
      vx.medium = state.medium;
      vx.sigma_rho = media.sigma(state.medium) * concentration_at(sm.density, *x);
      record(std::move(vx));
      if (path.size() >= max_vertices) return;
      const auto phase_pdf = continue_from_medium(scene, sm, *x, static_cast<int>(path.size()), state.medium,
                                                  state.beta, state.mis, state.ray, rng);
      if (!phase_pdf) return;
      set_reverse(phase_value(sm.phase, -state.ray.direction, path.back().wo));
      state.pdf_dir = *phase_pdf;
      state.parallel = false;
      state.start = *x;
      tau = 0.0;
      continue;
    }
    tau += scattering_depth(v, media, state.medium, state.start, d, length(hit->point - state.start));
    if (state.beta.is_zero()) return;
    if (surface.kind == SurfaceKind::emitter) {  // lamps absorb what reaches them
      if (mode == TransportMode::radiance) {
        Vertex<N> x = next_vertex(VertexKind::light, hit->point, state, tau);
        x.normal = hit->normal;
        x.hit = *hit;
        x.light = surface.first_light + static_cast<int>(hit->primitive);
        record(std::move(x));
      }
      return;
    }
    if (surface.index_matched) {
      if (!cross_index_matched(surface, *hit, state.crossings, state.medium, state.start, state.ray)) return;
      continue;
    }
    const Vec3 wo = -d;
    Vertex<N> vx = next_vertex(VertexKind::surface, hit->point, state, tau);
    vx.normal = hit->normal;
    vx.hit = *hit;
    vx.event = surface_event(v, *hit, surface, wo, state.medium, w);
    vx.delta = is_specular(vx.event.bsdf);
    record(std::move(vx));
    if (path.size() >= max_vertices) return;
    const SurfaceEvent<N>& e = path.back().event;
    const auto bsdf_pdf = continue_path(scene, *hit, e, wo, mode, static_cast<int>(path.size()), state.beta,
                                        state.medium, state.ray, rng, mean_ratio(scene, state.mis.r_u));
    if (!bsdf_pdf) return;
    const bool delta = path.back().delta;
    set_reverse(delta ? 0.0 : pdf(e.bsdf, e.frame.to_local(state.ray.direction), e.frame.to_local(wo)));
    state.pdf_dir = delta ? 0.0 : *bsdf_pdf;
    state.parallel = false;
    state.start = hit->point;
    tau = 0.0;
  }
}

#define BOUGUER_WALK_INSTANTIATE(N)                                                                             \
  template void random_walk(const SceneView<N>&, const WalkMedia&, TransportMode, WalkState<N>&, std::size_t, \
                            const SampledWavelengths<N>&, Rng&, std::uint64_t&, std::vector<Vertex<N>>&);
BOUGUER_WALK_INSTANTIATE(kFullBins)
BOUGUER_WALK_INSTANTIATE(3)
BOUGUER_WALK_INSTANTIATE(kHeroCount)
#undef BOUGUER_WALK_INSTANTIATE

}  // namespace bouguer
