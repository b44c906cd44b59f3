#pragma once
// Changing a compiled scene in place (Mitsuba's traverse/update habit): what a sweep of renders
// changes between frames, without compiling the geometry again. Each update rewrites only the
// parts of the RenderScene that depend on the value (a medium's absorption spectra, an emitter's
// spectrum and the light powers, the camera),
// from the SceneDesc the scene was compiled from, so that the scene renders exactly as a fresh
// compile of the description with that value would; the description is left as loaded.
// Errors are bouguer::Error naming `where` (as the builder's checks do).
#include <string>

#include "bouguer/scene/compile.h"
#include "bouguer/scene/description.h"
#include "bouguer/scene/source.h"

namespace bouguer {

// The medium's names, for messages ("glass, water or milk").
std::string medium_names(const SceneDesc& desc);

// Multiplies the absorption of medium `name` (σ_a, or each absorber's σ_a per unit concentration)
// by `factor` against the description, so factor 1 is the scene as loaded: σ_a is linear in the
// concentration (Beer), so a concentration sweep is a sweep of this factor. The index and any
// scattering are unchanged.
void set_absorption_scale(RenderScene& scene, const SceneDesc& desc, const std::string& name, double factor,
                          const Source& where);

// Multiplies the emission of `object` (an emitter) or of "background" by `factor` against the
// description (factor 1: as loaded); the light powers and selection distributions follow.
void set_emission_scale(RenderScene& scene, const SceneDesc& desc, const std::string& object, double factor,
                        const Source& where);

// The light powers (luminance flux, for the scene's bounds) and the two light-selection
// distributions from the lights' spectra: compile's last step, and again after an emission changes.
void set_light_distributions(RenderScene& scene);

// The camera for the next renders: checked as the scene file's camera is (SceneBuilder::camera).
void set_camera(RenderScene& scene, const SceneDesc& desc, const CameraDesc& camera, const Source& where);

}  // namespace bouguer
