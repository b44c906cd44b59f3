#pragma once
// Running the settings' integrator: the estimators bound to their names (scene/render_modes.h),
// over any pixel region and sample range of a film (render/render.h makes and resolves films).
#include <functional>

#include "bouguer/render/render.h"

namespace bouguer {

// Renders `region` × `samples` into `film` with the settings' integrator; stats are added to.
void render_into(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                 SampleRange samples, const RenderControl& control, RenderStats& stats);

// A render in passes, each a range of the samples of every pixel from `first` on: 1, 1, 2, 4, ...
// samples a pass, each as many as the film has (at most max_pass_spp where that is > 0). Any split
// gives the same image (render/integrator.h), so a render stopped between passes has the whole
// image of the samples done, early. Passes stay few (log2 spp + 1): each walks the whole film
// again, which cost rgb3 Whitted 5–15 % when passes were capped at a sixteenth of the samples.
// With a budget of seconds, a pass that would not end within it is cut to the samples that will
// at the rate measured so far, and none is begun when not one more would (the image then depends
// on the machine's speed). control.cancel stops it: the pass in flight keeps the tiles it ended.
struct PassOptions {
  int first = 0;          // samples per pixel the film has already (an automatic choice's trial)
  double budget_s = 0.0;  // 0: none
  int max_pass_spp = 0;   // 0: passes double without bound
  // (begin, end, the fraction of the pass's tiles done), from any thread.
  std::function<void(int begin, int end, double fraction)> progress;
  // After each whole pass, the samples per pixel every pixel has: false ends the render (adaptive
  // sampling's pixels all done, a caller that stopped it).
  std::function<bool(int complete)> after_pass;
};
struct Passes {
  int complete = 0;  // samples every pixel has
  int partial = 0;   // the stopped pass's samples, in the pixels it reached
  double partial_fraction = 0.0;  // of the stopped pass's tiles that finished
};
Passes render_passes(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film,
                     const RenderControl& control, const PassOptions& options, RenderStats& stats);

// The whole image in one call: every pixel, every sample.
Film render(const RenderScene& scene, const RenderSettings& settings, const RenderControl& control,
            RenderStats& stats, bool keep_spectra = false);

}  // namespace bouguer
