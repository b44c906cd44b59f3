#include "bouguer/integrators/render_into.h"

#include <algorithm>
#include <atomic>
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

Passes render_passes(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film,
                     const RenderControl& control, const PassOptions& options, RenderStats& stats) {
  const int spp = settings.spp, first = options.first;
  const auto start = std::chrono::steady_clock::now();
  Passes p;
  p.complete = first;
  auto stopped = [&] { return control.cancel && control.cancel->load(); };
  for (int begin = first; begin < spp && !stopped();) {
    int end = std::min(spp, begin + std::max(begin, 1));
    if (options.max_pass_spp > 0) end = std::min(end, begin + options.max_pass_spp);
    if (options.budget_s > 0.0 && begin > first) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double affordable = (options.budget_s - elapsed) / (elapsed / (begin - first));  // samples per pixel still in time
      if (affordable < 1.0) return p;
      end = std::min(end, begin + static_cast<int>(std::min(affordable, static_cast<double>(spp))));
    }
    std::atomic<double> fraction{0.0};
    RenderControl pass = control;
    pass.progress = [&, begin, end](double f) {
      fraction.store(f);
      if (options.progress) options.progress(begin, end, f);
    };
    render_into(scene, settings, film, PixelRegion::whole(scene.camera), {begin, end}, pass, stats);
    if (stopped()) {
      if (fraction.load() >= 1.0) p.complete = end;
      else p.partial = end - begin, p.partial_fraction = fraction.load();
      return p;
    }
    p.complete = begin = end;
    if (options.after_pass && !options.after_pass(p.complete)) return p;
  }
  return p;
}

Film render(const RenderScene& scene, const RenderSettings& settings, const RenderControl& control,
            RenderStats& stats, bool keep_spectra) {
  check_settings(scene, settings, keep_spectra);
  // Samples [first, spp) of `chosen`'s estimator into `film`, guided where the settings ask for it.
  auto rest = [&](const RenderSettings& chosen, FilmBuffer& film, int first) {
    GuideTraining training;
    const auto guide = prepare_guide(scene, chosen, control, stats, training);
    RenderControl guided = control;
    if (guide) guided.guide = guide.get();
    render_into(scene, chosen, film, PixelRegion::whole(scene.camera), {first, settings.spp}, guided, stats);
    return resolve(film, settings.spp);
  };
  if (settings.integrator == IntegratorType::automatic) {
    EstimatorChoice choice =
        choose_estimator(scene, settings, auto_trial_spp(settings.spp), settings.spp, keep_spectra, nullptr, control,
                         stats);
    RenderSettings chosen = settings;
    chosen.integrator = choice.chosen;
    chosen.light_paths = chosen.light_paths || choice.light_paths;
    FilmBuffer film = choice.film ? std::move(*choice.film) : make_film(scene, keep_spectra);
    return rest(chosen, film, choice.trial_spp);
  }
  FilmBuffer film = make_film(scene, keep_spectra);
  return rest(settings, film, 0);
}

}  // namespace bouguer
