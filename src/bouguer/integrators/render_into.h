#pragma once
// Running the settings' integrator: the estimators bound to their names (scene/render_modes.h),
// over any pixel region and sample range of a film (render/render.h makes and resolves films).
#include "bouguer/render/render.h"

namespace bouguer {

// Renders `region` × `samples` into `film` with the settings' integrator; stats are added to.
void render_into(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                 SampleRange samples, const RenderControl& control, RenderStats& stats);

// The whole image in one call: every pixel, every sample.
Film render(const RenderScene& scene, const RenderSettings& settings, const RenderControl& control,
            RenderStats& stats, bool keep_spectra = false);

}  // namespace bouguer
