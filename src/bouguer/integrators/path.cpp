// The unidirectional spectral path tracer. Next-event estimation (integrators/direct_light.h) combined
// with BSDF sampling by multiple importance sampling (power heuristic). At a smooth interface the
// path reflects with probability F and refracts otherwise (weight 1: the Fresnel factor cancels),
// so the same interface and medium model as the Whitted integrator hold, and both converge to the
// same image. Shadow rays are blocked by any surface; light reaches diffuse surfaces through glass
// along BSDF-sampled paths (caustics, coloured shadows).
// Russian roulette starts at depth 4 and is never played where the medium forbids it (inside an
// absorber, media/medium.h); the survival probability is the largest throughput over
// wavelengths, at least 5 %.
// Dispersion: at the first dispersive interface the path keeps one wavelength (keep_one_wavelength;
// its choice stratified over the pixel's samples by the caller) and follows n(λ) from there on;
// each wavelength's expected contribution is unchanged.
// Scattering media: delta tracking of the scattering with spectral MIS (media/scattering.h), the
// absorption in closed form; next-event estimation at every medium vertex through the phase
// function, and near the boundary of a dense medium next-event estimation through its smooth
// interfaces to the environment map (exit_guide.h: ExitGuide); Russian roulette by throughput there
// too. Scattering events do not count against max_depth; a path stops after kMaxScatterings of
// them (integrators/scene_view.h). Index-matched interfaces are crossed without a vertex.
// The walk is the one random walk of integrators/walk.h; radiance.h is its visitor.
// Path guiding (integrators/guiding.h): where the render control carries a trained guide, half the
// directions at diffuse surfaces are drawn from it.
// Light paths (render.light_paths; light.cpp): after each camera sample, its light path from a point,
// spot or distant lamp, splatted only where next-event estimation does not make it.
#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/radiance.h"

namespace bouguer {
void render_path(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                 SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    render_camera_paths<N>(scene, settings, film, region, range, control, stats,
                           [guide = control.guide](const SceneView<N>& v, const Ray& ray, SampledWavelengths<N>& w,
                                                   double dispersion_u, Rng& rng, std::uint64_t& rays) {
                             return path_radiance(v, ray, w, dispersion_u, rng, rays, guide);
                           },
                           settings.light_paths && !scene.delta_lights.empty(), settings.shell_transport);
  });
}

}  // namespace bouguer
