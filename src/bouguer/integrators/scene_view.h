#pragma once
// What every event of a path reads, and the limits every walk keeps: the compiled scene with its
// spectra for this render's mode and the camera (SceneView), the bounds on a path's scattering
// events and index-matched crossings, and two questions about a scene medium (does it absorb,
// does it scatter). Contract: nothing here changes the scene or a path.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>

#include "bouguer/core/frame.h"
#include "bouguer/core/rng.h"
#include "bouguer/lights/environment.h"
#include "bouguer/materials/surface_bsdf.h"
#include "bouguer/media/scattering.h"
#include "bouguer/render/camera.h"
#include "bouguer/scene/compile.h"

namespace bouguer {

class ShellSet;

// A path's scattering events, and the index-matched interfaces it crosses, are not bounded by
// max_depth (a dense medium needs thousands); these stop a path that would never end.
inline constexpr int kMaxScatterings = 100000;
inline constexpr int kMaxCrossings = 1024;

// What every event reads: the compiled scene, its spectra for this render's mode, the camera.
template <std::size_t N>
struct SceneView {
  const RenderScene& scene;
  const SpectralTables<N>& tables;
  const Camera& camera;
  int max_depth = 32;
  bool exit_guide = true;  // the path tracer's ExitGuide (exit_guide.h)
  bool manifold = true;    // the path tracer's next-event estimation through glass (manifold.h)
  // With it, area and spherical lamps through chains of mesh faces and exact cylinders' sides:
  // all, none, or (unset) the compiled scene's small lamps (Surface::small_lamp).
  std::optional<bool> area_lamp_chains = std::nullopt;
  bool lamp_through_chains(std::uint32_t emitter_geometry) const {
    return area_lamp_chains.value_or(scene.surfaces[emitter_geometry].small_lamp);
  }
  bool any_lamp_through_chains() const { return area_lamp_chains.value_or(scene.small_lamps); }
  // transmission (direct_light.h) asks only whether a segment is clear: no medium is tracked, so
  // nothing is drawn and the transmittance is 1 (manifold.h: next_event_makes, a geometric question).
  bool visibility_only = false;
  // The path tracer's shell transport (integrators/shell_hops.h): the tables of the render call's
  // samples (null: none) and the sample whose camera path is being walked.
  const ShellSet* shells = nullptr;
  int sample = 0;
};

inline bool absorbs(const RenderScene& scene, int medium) {
  return medium >= 0 && absorbs(scene.media[static_cast<std::size_t>(medium)].medium);
}

// The scattering medium `medium` is, or null.
inline const ScatteringMedium* scattering_medium(const RenderScene& scene, int medium) {
  return medium < 0 ? nullptr : scattering(scene.media[static_cast<std::size_t>(medium)].medium);
}

}  // namespace bouguer
