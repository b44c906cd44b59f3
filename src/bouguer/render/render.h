#pragma once
// Rendering a compiled scene: a film for the camera (keeping spectra when asked), filled by the
// settings' integrator over any pixel region and sample range (integrators/render_into.h), then
// resolved into the image.
#include <cstdint>

#include "bouguer/render/integrator.h"

namespace bouguer {

// The film a render of this scene fills; spectra at the full mode's bin centres when asked.
// `denoised`: the film keeps its half buffers from its first sample (render/denoise.h), and the
// memory checked before it is allocated is the denoising's too, so that a render is not lost to
// it afterwards.
FilmBuffer make_film(const RenderScene& scene, bool keep_spectra, bool denoised = false);

// Checks that the settings fit the scene (an Error naming the scene file otherwise).
void check_settings(const RenderScene& scene, const RenderSettings& settings, bool keep_spectra);

// The image of a film after `samples_done` samples per pixel (splats scaled by 1 / that).
Film resolve(const FilmBuffer& film, int samples_done);

}  // namespace bouguer
