#pragma once
// The estimators: each renders a pixel region and a sample range into a film (render/integrator.h).
//   whitted: the paper's ray tracer (integrators/whitted.cpp),
//   path:    unidirectional spectral path tracing with next-event estimation (path.cpp),
//   light:   light tracing, paths from the emitters connected to the camera (light.cpp),
//   bdpt:    bidirectional path tracing over one random walk (bdpt.cpp, bidirectional.h, walk.h),
//   vcm:     vertex connection and merging: bdpt and photon mapping under one MIS (vcm.cpp).
#include <optional>
#include <vector>

#include "bouguer/integrators/events.h"
#include "bouguer/integrators/shell_hops.h"
#include "bouguer/render/integrator.h"
#include "bouguer/render/sampling.h"

namespace bouguer {

// The salts of the hero's strata and of the split's bins (start_sample_wavelengths).
inline constexpr std::uint64_t kHeroStrataSalt = 1;
inline constexpr std::uint64_t kSplitStrataSalt = 2;

void render_whitted(const RenderScene&, const RenderSettings&, FilmBuffer&, PixelRegion, SampleRange,
                    const RenderControl&, RenderStats&);
void render_path(const RenderScene&, const RenderSettings&, FilmBuffer&, PixelRegion, SampleRange,
                 const RenderControl&, RenderStats&);
void render_light(const RenderScene&, const RenderSettings&, FilmBuffer&, PixelRegion, SampleRange,
                  const RenderControl&, RenderStats&);
// The path tracer's light paths (render.light_paths): after each camera sample, one light path
// from a point, spot or distant lamp (drawn by power among them: RenderScene::delta_lamps), splatted only
// where the path tracer's next-event estimation does not make the path (light.cpp). Their
// streams' salt (render/sampling.h: sample_rng), apart from every other's.
inline constexpr std::uint64_t kLightPathsSalt = 5;
template <std::size_t N>
void trace_light_path_beyond_next_event(const SceneView<N>& v, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                                        FilmBuffer& film, std::uint64_t& rays);
void render_bdpt(const RenderScene&, const RenderSettings&, FilmBuffer&, PixelRegion, SampleRange,
                 const RenderControl&, RenderStats&);
void render_vcm(const RenderScene&, const RenderSettings&, FilmBuffer&, PixelRegion, SampleRange,
                const RenderControl&, RenderStats&);

// Camera sample s's radiance into its pixel (and its spectrum, where the film keeps spectra; s's
// parity: the half it belongs to, where the film keeps halves).
template <std::size_t N>
void add_camera_sample(FilmBuffer& film, const SpectralTables<N>& tables, const SampledWavelengths<N>& w, int x, int y,
                       int s, const SampledSpectrum<N>& l) {
  const Vec3 rgb = tables.to_linear_rgb(l, w);
  const bool odd = (s & 1) != 0;
  if (film.has_spectra())
    film.add_sample(x, y, rgb, 1.0, std::span<const float>(l.v.data(), N), odd);
  else
    film.add_sample(x, y, rgb, 1.0, {}, odd);
}

// Sample s's wavelengths and hero (media_travel.h: draw_hero): hero mode's four wavelengths from
// `strata` (the pixel's wavelength strata; the fixed modes carry theirs), the hero's index from
// `heroes`, strata of its own, so that it stays independent of the wavelengths and of the one kept
// at a dispersive interface (both drawn from `strata`), and each index is the hero equally often.
// Full mode's split at a dense chromatic medium places its bins with `splits`, strata of a third
// salt: independent of the hero, whose majorant drew the distances before the split (a bin choice
// tied to the hero would weight each bin right only on average over heroes, not for the path).
template <std::size_t N>
void start_sample_wavelengths(const RenderScene& scene, const SpectralTables<N>& tables, const WavelengthStrata& strata,
                              const WavelengthStrata& heroes, const WavelengthStrata& splits, int s,
                              SampledWavelengths<N>& w) {
  tables.restart(w, tables.mode() == SpectralMode::hero ? strata.u(s) / static_cast<double>(N) : 0.0);
  draw_hero(scene, w, scene.scatters ? heroes.u(s) : 0.0);
  w.split_u = scene.scatters ? splits.u(s) : 0.0;
}

// Every sample of every pixel of `region` × `range`, tiles in parallel: each with its own random
// stream (seed, pixel, sample, salt) and its wavelengths and hero (start_sample_wavelengths: hero
// mode stratifies its wavelengths over the pixel's samples in a shuffled order; the fixed modes
// stratify the wavelength kept at a dispersive interface instead; the hero of scattering media is
// stratified in every mode, for every estimator that draws its samples here: media_travel.h), handed to
// sample(x, y, s, rng, wavelengths, dispersion_u, rays). An estimator that never keeps one
// wavelength (kDispersion false: Whitted) gets dispersion_u 0 in the fixed modes, and the strata
// are not drawn for it.
template <std::size_t N, bool kDispersion = true, typename Sample>
void for_each_pixel_sample(const RenderScene& scene, const SpectralTables<N>& tables, const RenderSettings& settings, int film_width,
                           PixelRegion region, SampleRange range, const RenderControl& control, RenderStats& stats,
                           std::uint64_t salt, Sample sample) {
  const bool hero = settings.spectral == SpectralMode::hero;
  for_each_tile(region, control, stats, [&](const PixelRegion& tile, std::uint64_t& rays) {
    WavelengthStrata strata, heroes, splits;
    SampledWavelengths<N> w = tables.wavelengths(0.0);
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        const auto pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(film_width) +
                           static_cast<std::uint64_t>(x);
        if (control.active && !(*control.active)[pixel]) continue;  // (adaptive sampling: done)
        const bool stratify = hero || (kDispersion && scene.dispersive);
        if (stratify) strata.reset(settings.seed, pixel, settings.spp);
        if (scene.scatters) {
          heroes.reset(settings.seed, pixel, settings.spp, kHeroStrataSalt);
          splits.reset(settings.seed, pixel, settings.spp, kSplitStrataSalt);
        }
        for (int s = range.begin; s < range.end; ++s) {
          Rng rng = sample_rng(settings.seed, pixel, s, salt);
          start_sample_wavelengths(scene, tables, strata, heroes, splits, s, w);
          const double dispersion_u = hero ? rng.next_double() : stratify ? strata.u(s) : 0.0;
          sample(x, y, s, rng, w, dispersion_u, rays);
        }
      }
  });
}

// The camera-sample loop of the estimators that trace from the camera: a camera ray through a
// stratified sub-pixel position and li(view, ray, wavelengths, dispersion_u, rng, rays) → radiance.
// With `light_paths` (the path tracer's, render.light_paths), each sample then traces its light
// path, with the wavelengths the sample began with, in the same loop (so a pass cut short has the
// light paths of the samples it took, as the splats' scale counts them).
// With `shells` (the path tracer's, render.shell_transport), its walks take spheres of shell
// transport from tables made before the tiles start (shell_hops.h): for at most kShellChunkSamples
// samples at a time, the call's samples walked chunk by chunk (each pixel still takes its samples
// in order, as separate calls over consecutive ranges would: the same image bit for bit), unless
// the control carries tables for all of them.
template <std::size_t N, bool kDispersion = true, typename Li>
void render_camera_paths(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film,
                         PixelRegion region, SampleRange range, const RenderControl& control, RenderStats& stats,
                         Li li, bool light_paths = false, bool shells = false) {
  const SpectralTables<N> tables(scene.spectra, settings.spectral);
  const Camera camera(scene.camera);
  const bool given = shells && scene.scatters && control.shells && control.shells->covers(scene, settings.seed, range);
  std::optional<ShellSet> own;  // (kept only where some medium gets tables)
  if (shells && scene.scatters && !given && own.emplace(scene, settings.seed).empty()) own.reset();
  const int samples = std::max(0, range.end - range.begin);
  const int chunk = own ? kShellChunkSamples : std::max(1, samples);
  const int chunks = std::max(1, (samples + chunk - 1) / chunk);
  for (int c = 0; c < chunks; ++c) {
    if (c > 0 && control.cancel && control.cancel->load()) break;  // (before the next chunk's tables)
    const SampleRange part{range.begin + c * chunk, std::min(range.end, range.begin + (c + 1) * chunk)};
    if (own) own->make(part, control.threads);
    SceneView<N> view{scene, tables, camera, settings.max_depth, exit_guide_enabled(settings, scene),
                      settings.manifold, settings.area_lamp_chains};
    if (given && !control.shells->empty()) view.shells = control.shells;
    if (own) view.shells = &*own;
    // (Progress by samples, as one call over the whole range would report it: a pass cut short
    // scales its light paths' splats by it, render_into.h.)
    RenderControl this_chunk = control;
    if (chunks > 1 && control.progress)
      this_chunk.progress = [&, part](double f) {
        control.progress((part.begin - range.begin + f * (part.end - part.begin)) / samples);
      };
    for_each_pixel_sample<N, kDispersion>(scene, tables, settings, film.width(), region, part, this_chunk, stats, 0,
                             [&](int x, int y, int s, Rng& rng, SampledWavelengths<N>& w, double dispersion_u,
                                 std::uint64_t& rays) {
                               const std::uint64_t pixel = pixel_index(x, y, film.width());
                               std::optional<SampledWavelengths<N>> began;
                               if (light_paths) began = w;
                               const auto [u, v] = subpixel(s, settings.spp, settings.seed, pixel, rng);
                               SceneView<N> at = view;
                               at.sample = s;
                               const SampledSpectrum<N> l =
                                   li(at, camera.generate_ray(x + u, y + v), w, dispersion_u, rng, rays);
                               add_camera_sample(film, tables, w, x, y, s, l);
                               if (!began) return;
                               Rng light_rng = sample_rng(settings.seed, pixel, s, kLightPathsSalt);
                               trace_light_path_beyond_next_event(view, *began, dispersion_u, light_rng, film, rays);
                             });
  }
}

}  // namespace bouguer
