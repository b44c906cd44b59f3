#include "bouguer/integrators/render_into.h"

#include <algorithm>
#include <chrono>

#include "bouguer/core/error.h"
#include "bouguer/integrators/choose.h"
#include "bouguer/integrators/guiding.h"
#include "bouguer/integrators/integrators.h"

namespace bouguer {
namespace {

RenderFn render_function(IntegratorType type) {
  switch (type) {
    case IntegratorType::whitted: return render_whitted;
    case IntegratorType::path: return render_path;
    case IntegratorType::light: return render_light;
    case IntegratorType::bdpt: return render_bdpt;
    case IntegratorType::vcm: return render_vcm;
    case IntegratorType::automatic: break;  // resolved by choose_estimator before any rendering
  }
  fail("internal error: integrator {} has no render function", static_cast<int>(type));
}

}  // namespace

void render_into(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                 SampleRange samples, const RenderControl& control, RenderStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  region.x1 = std::min(region.x1, film.width());
  region.y1 = std::min(region.y1, film.height());
  samples.end = std::min(samples.end, settings.spp);
  if (samples.begin < samples.end) render_function(settings.integrator)(scene, settings, film, region, samples, control, stats);
  stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Film render(const RenderScene& scene, const RenderSettings& settings, const RenderControl& control,
            RenderStats& stats, bool keep_spectra) {
  check_settings(scene, settings, keep_spectra);
  if (settings.integrator == IntegratorType::automatic) {
    EstimatorChoice choice =
        choose_estimator(scene, settings, auto_trial_spp(settings.spp), keep_spectra, nullptr, control, stats);
    RenderSettings chosen = settings;
    chosen.integrator = choice.chosen;
    FilmBuffer film = choice.film ? std::move(*choice.film) : make_film(scene, keep_spectra);
    GuideTraining training;
    const auto guide = prepare_guide(scene, chosen, control, stats, training);
    RenderControl guided = control;
    if (guide) guided.guide = guide.get();
    render_into(scene, chosen, film, PixelRegion::whole(scene.camera), {choice.trial_spp, settings.spp}, guided,
                stats);
    return resolve(film, settings.spp);
  }
  FilmBuffer film = make_film(scene, keep_spectra);
  GuideTraining training;
  const auto guide = prepare_guide(scene, settings, control, stats, training);
  RenderControl guided = control;
  if (guide) guided.guide = guide.get();
  render_into(scene, settings, film, PixelRegion::whole(scene.camera), {0, settings.spp}, guided, stats);
  return resolve(film, settings.spp);
}

}  // namespace bouguer
