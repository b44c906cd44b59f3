#pragma once
// The light tracer's splats: a light path's vertex (a surface, a medium vertex, the lamp itself)
// connected to the camera by a shadow ray and added at its film position. Contract: what is
// splatted is the vertex's importance-mode throughput times the connection's value, divided by
// the path's mean spectral-MIS ratio; the film's fixed-point sums make it order-independent.
#include "bouguer/integrators/direct_light.h"
#include "bouguer/render/film.h"

namespace bouguer {

// A light path's contribution l (all carried wavelengths) at film position (x, y), in pixels.
template <std::size_t N>
void add_splat(FilmBuffer& film, const SpectralTables<N>& tables, const SampledWavelengths<N>& w, double x, double y,
               const SampledSpectrum<N>& l) {
  if (film.has_spectra())
    film.add_splat(x, y, tables.to_linear_rgb(l, w), std::span<const float>(l.v.data(), N));
  else
    film.add_splat(x, y, tables.to_linear_rgb(l, w));
}

// Which of a vertex's paths to the camera a splat makes: all (the straight connection, and through
// smooth glass to a pinhole where the straight one meets it or a caster), or those through the
// glass alone (bdpt: Bdpt::through_glass_to_camera, its straight one being t = 1).
enum class CameraPaths { all, through_glass };

// A light-path vertex at a non-specular surface, arrived at along wo (towards the light): the
// light it sends to the camera, through the medium on the camera's side, splatted at its film
// position. The throughput beta carries importance-mode weights; path_r_u the path's ratios.
template <std::size_t N>
void splat_surface_to_camera(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                             const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w,
                             const SampledSpectrum<N>& path_r_u, Rng& rng, FilmBuffer& film, std::uint64_t& rays,
                             CameraPaths which = CameraPaths::all);

// The same for a scattering event of a light path (direct_light.h: MediumPoint, its direction the
// one the light arrived along).
template <std::size_t N>
void splat_medium_to_camera(const SceneView<N>& v, const MediumPoint& at, const SampledSpectrum<N>& beta,
                            const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                            FilmBuffer& film, std::uint64_t& rays, CameraPaths which = CameraPaths::all);

// A light path's first vertex on a surface emitter (an area light or a sphere: the lamp seen
// directly), `at` with the emitter's outward normal: `beta` is the emitted radiance over the
// densities of choosing the light and the point; medium is the one in front.
template <std::size_t N>
void splat_light_to_camera(const SceneView<N>& v, const Hit& at, const Light& light, int medium,
                           const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w, Rng& rng,
                           FilmBuffer& film, std::uint64_t& rays);

}  // namespace bouguer
