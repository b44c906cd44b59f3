#pragma once
// The display transform of a rendered scene (io/display.h): the scene's description of it,
// resolved against the finished film and, for white balance to the brightest emitter, the
// compiled scene's lights.
#include <optional>

#include "bouguer/io/display.h"
#include "bouguer/scene/compile.h"

namespace bouguer {

// The CIE 1931 XYZ (at Y = 1) of the light of largest luminous power (RenderScene::light_power;
// an emitting mesh's triangles summed by the spectrum they share): an emitter's, point, spot or
// distant light's spectrum (a textured emitter's untextured spectrum), the background's, or an
// environment map's mean colour over the sphere. nullopt for a scene without light or whose
// brightest light has no luminance.
std::optional<Vec3> brightest_emitter_white_xyz(const RenderScene& scene);

// resolve_display with the brightest emitter's white when the description asks for it.
DisplayTransform display_transform(const RenderScene& scene, const DisplayDesc& d, const Film& film);

}  // namespace bouguer
