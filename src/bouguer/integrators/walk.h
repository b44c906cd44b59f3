#pragma once
// One random walk for camera and light subpaths (pbrt-v4's RandomWalk, Tungsten's TraceBase): a
// subpath as a list of vertex records, each with what a connection and its MIS weight need. The
// bidirectional estimator (integrators/bdpt.cpp) builds both of its subpaths with it.
//
// Densities. pdf_fwd is the density with which the walk produced the vertex, pdf_rev the one with
// which a walk from the other end would have; both per unit area at the vertex (per unit solid
// angle for a light at infinity), and both include the distance density of the segment in a
// scattering medium: exp(−τ) to pass through it, times σ̄_s·ρ(x) to stop at a medium vertex. They
// serve only as MIS weights, which need not be the estimator's own densities, only the same
// function of the path for every strategy: τ uses σ̄_s, the mean σ_s over the wavelengths carried
// when the sample began (not the hero's), so the weights do not depend on which wavelength drew
// the distances, and the spectral MIS over wavelengths (media/scattering.h) stays unbiased
// beneath them. The throughput beta and the ratios r_u are the estimator's own.
#include <cstdint>
#include <span>
#include <vector>

#include "bouguer/integrators/events.h"

namespace bouguer {

enum class VertexKind : std::uint8_t { camera, light, surface, medium };

template <std::size_t N>
struct Vertex {
  VertexKind kind = VertexKind::surface;
  Vec3 point;
  Vec3 normal;  // unit geometric normal: surfaces and area lights; zero elsewhere
  Hit hit;      // surfaces and area lights: where rays leave from
  SurfaceEvent<N> event{Frame(Vec3{0.0, 0.0, 1.0}), DiffuseReflection<N>{}};
  int medium = -1;            // medium vertices: the medium they sit in
  double sigma_rho = 0.0;     // medium vertices: σ̄_s·ρ(x), the density of stopping here
  Vec3 wo;                    // unit, towards the previous vertex of the subpath (zero at its start)
  double tau_in = 0.0;        // σ̄_s·∫ρ over the segment from the previous vertex
  SampledSpectrum<N> beta;    // the subpath's throughput up to here, divided by its densities
  SampledSpectrum<N> r_u = SampledSpectrum<N>::constant(1.0f);  // its spectral-MIS ratios so far
  double pdf_fwd = 0.0, pdf_rev = 0.0;
  bool delta = false;  // a specular surface: never connected
  // Light endpoints (the start of a light subpath, or where a camera subpath met a lamp or escaped).
  int light = -1;
  bool infinite = false;  // background, environment or distant light (no point)
  Vec3 light_dir;         // infinite: unit, from the scene towards where the light comes from

  bool on_surface() const { return normal != Vec3{}; }
  bool connectible() const { return !delta; }
};

// What a walk needs besides the scene: the mean σ_s of every medium (0 for those that do not
// scatter) over the wavelengths the sample began with, which the MIS densities use.
struct WalkMedia {
  std::span<const double> sigma_mean;
  double sigma(int medium) const { return medium < 0 ? 0.0 : sigma_mean[static_cast<std::size_t>(medium)]; }
};

// The state a walk continues from: the ray leaving the last vertex, where the current segment
// began (a vertex or a medium boundary), the medium it travels in, the throughput and ratios,
// and the solid-angle density of the ray's direction (0: specular).
template <std::size_t N>
struct WalkState {
  Ray ray;
  Vec3 start;
  int medium = -1;
  SampledSpectrum<N> beta = SampledSpectrum<N>::constant(1.0f);
  SpectralMis<N> mis;
  double pdf_dir = 0.0;
  bool parallel = false;  // pdf_dir is per unit area across parallel rays (orthographic camera,
                          // light at infinity): the first vertex's density is pdf_dir·|cos θ|
  int crossings = 0;
};

// Converts a solid-angle density at `from` towards `to` into one per unit area at `to` (none for
// a light at infinity), times the segment's distance density.
template <std::size_t N>
double to_area_density(double pdf_dir, const Vec3& from, const Vertex<N>& to, double tau, bool parallel = false) {
  double pdf = pdf_dir;
  if (parallel) {
    if (to.on_surface()) pdf *= std::abs(dot(to.normal, normalize(to.point - from)));
  } else if (!to.infinite) {
    const Vec3 d = to.point - from;
    const double d2 = dot(d, d);
    if (!(d2 > 0.0)) return 0.0;
    if (to.on_surface()) pdf *= std::abs(dot(to.normal, d)) / std::sqrt(d2);
    pdf /= d2;
  }
  if (tau > 0.0) pdf *= std::exp(-tau);
  if (to.kind == VertexKind::medium) pdf *= to.sigma_rho;
  return pdf;
}

// Extends `path` from `state` by at most max_vertices − path.size() vertices, in the transport
// mode of the subpath (radiance: from the camera, which then also records where it meets a lamp
// or escapes to a light at infinity; importance: from a light). Each vertex's pdf_fwd is set, and
// the previous vertex's pdf_rev. Russian roulette and the medium tracking as the path tracer.
template <std::size_t N>
void random_walk(const SceneView<N>& v, const WalkMedia& media, TransportMode mode, WalkState<N>& state,
                 std::size_t max_vertices, const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays,
                 std::vector<Vertex<N>>& path);

}  // namespace bouguer
