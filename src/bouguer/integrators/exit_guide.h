#pragma once
// The path tracer's next-event estimation through smooth interfaces to the environment map (#20),
// at a medium vertex near a dense medium's boundary (exit_guide_at, environment_through_interfaces)
// and at a surface whose shadow ray glass blocks (surface_exit_guide, carried on by direct_light),
// and the density the walk's own exits are weighted against it with (exit_guide_pdf). Contract:
// the guide only shapes a density; a wrong guess makes a connection noisier, never biased.
#include "bouguer/integrators/dense_media.h"
#include "bouguer/integrators/surface_events.h"

namespace bouguer {

// How far a connection through the interfaces may go: as many surfaces as the walk could still
// cross (its max_depth less the surfaces it has met), and the walk's count of index-matched
// crossings so far (it stops where the walk would, past kMaxCrossings).
struct ThroughInterfaces {
  int surfaces_left = 0;
  int crossings = 0;
};

// What carry_to_environment does where it enters a scattering medium: stop (a surface's guide:
// many wavelengths ride on it), or go on with the transmittance in closed form (a medium vertex's
// guide, on a walk of one wavelength: ratio tracking against a homogeneous medium's own majorant
// would give 0 or 1).
enum class ScatteringMedia : std::uint8_t { stop, closed_form };

// `seg` carried on through the smooth interfaces it meets, refracting and transmitting (1 − F) at
// each, to the map: tr times what arrives there once at least one interface is crossed. Zero where
// it meets any other surface, escapes without crossing one (next-event estimation's own), would
// cross more than `surfaces_left` interfaces or kMaxCrossings index-matched boundaries (where the
// walk would stop), would keep one wavelength at a dispersive interface, or enters a scattering
// medium where `scattering` says stop.
template <std::size_t N>
SampledSpectrum<N> carry_to_environment(const SceneView<N>& v, RaySegment seg, SampledSpectrum<N> tr,
                                        const SampledWavelengths<N>& w, std::uint64_t& rays, int surfaces_left,
                                        ScatteringMedia scattering);

// Next-event estimation through the interfaces (the path tracer, #20). A connection stops at any
// surface but an index-matched one, so a dense medium inside glass or below a water surface gets
// no direct light: its light comes from walks that leave by chance in a direction that meets the
// bright part of the environment map. Under a studio map that was most of a glass of milk's noise
// (seed against seed, mean ΔE00 9.5 at 64 spp against 3.2 under a uniform sky of the same
// brightness). So a medium vertex of a walk of one wavelength (after a split or a dispersive
// interface) in a homogeneous medium, within kExitGuideDepth mean free paths of a surface, also
// draws a direction from the map carried into the medium through a refraction at a guessed plane:
// its normal points from the vertex to the nearest surface point (RayScene::distance_to_surfaces),
// its relative index is the medium's over the world's (a thin parallel wall of glass between them
// bends a ray as one refraction does). It follows that direction to the surface and through the
// smooth interfaces it meets, each transmitting (1 − F), to the map
// (environment_through_interfaces). The guess only shapes a density: where it is wrong the
// connection is noisier, never biased. The walk's own paths that leave the same way (a
// phase-function direction, no event before the surface, refractions only) are weighted against
// it by the power heuristic (the walk keeps the guide of its last medium vertex: GuideTrail,
// below).
inline constexpr double kExitGuideDepth = 3.0;
inline constexpr std::uint64_t kExitGuideStream = 0x65786974;  // "exit"
// Unless the scene says (RenderSettings::exit_guide), the guide runs where the map's contrast
// (EnvironmentMap::contrast) is at least kExitGuideContrast. Under a smooth map a walk's own exits
// already see it about as well as the map's samples do, and the connections' transmittance to the
// surface only adds noise. Measured on the whole-milk glass (docs/performance.md): the studio map
// (contrast 12) guided 1.6 times the efficiency; blended towards its mean to contrast 4, even; the
// whole-milk ball under its grey sky (1.4), half; a white map (1), a fiftieth.
inline constexpr double kExitGuideContrast = 4.0;
inline bool exit_guide_enabled(const RenderSettings& settings, const RenderScene& scene) {
  if (settings.exit_guide) return *settings.exit_guide;
  return scene.environment && scene.environment->contrast >= kExitGuideContrast;
}
// Whether either guide (medium or surface, below) runs in this render: it is on and there is a map.
template <std::size_t N>
bool exit_guide_runs(const SceneView<N>& v) {
  return v.exit_guide && v.scene.environment && v.scene.environment_light >= 0;
}
struct ExitGuide {
  Vec3 normal;       // the guessed plane's, out of the medium
  double eta = 0.0;  // the medium's index over the world's; 0: no guide here
  bool from_surface = false;  // set at a surface vertex (below): the map's density, no plane
  int lobe = -1;  // a surface's: the map's lobe its next-event estimation drew from (direct_light.h)
  bool active() const { return eta > 0.0; }
};
template <std::size_t N>
ExitGuide exit_guide_at(const SceneView<N>& v, int medium, const Vec3& x, const SampledWavelengths<N>& w,
                        SurfaceDistance& last, InsideSet inside);
// The same at a surface (#20). Next-event estimation at a non-specular surface draws a direction
// from the map, and a smooth interface in the way (glass, a liquid's surface) stopped its shadow
// ray: the light that reaches a sweep through an empty glass's walls, or a clear liquid's coloured
// shadow, came only from BSDF directions that happened to meet the map's bright parts through
// them (speckle on the sweep around the glasses of `milk-and-juice`). With the guide on, that
// shadow ray goes on through the smooth interfaces it meets, refracting and transmitting (1 − F)
// at each, through media that only absorb, to the map (direct_light's `through`). No plane is
// guessed: the map's density of the first direction is the strategy's (a thin wall, or a vessel
// seen from outside, bends a ray little; where it bends more the connection is noisier, never
// biased). The walk's own paths that leave the same way (a BSDF direction, refractions only, no
// scattering medium, no wavelength kept at a dispersive interface on the way) are weighted against
// it as unblocked ones are against next-event estimation (radiance.h, walk.h).
inline ExitGuide surface_exit_guide(int lobe) { return {Vec3{}, 1.0, true, lobe}; }
// The guide a walk carries from its last medium or non-specular surface vertex (walk.h:
// GuidesExits; the path tracer's visitor holds it, radiance.h), the direction drawn there and its
// phase or BSDF density: a walk that leaves from there through smooth interfaces only, to the map,
// is weighted against the guide. Cleared at any other vertex but a smooth interface's refraction;
// a surface's also in a scattering medium and where the walk keeps one wavelength at a dispersive
// interface.
struct GuideTrail {
  ExitGuide guide;
  Vec3 dir;
  double phase_pdf = 0.0;
  void clear() { guide = {}; }
  void drew(const Vec3& d, double pdf) {
    dir = d;
    phase_pdf = pdf;
  }
};
// The guide's solid-angle density of the direction wi out of the vertex: the map's density of the
// direction wi refracts into at the plane, times |dω_out/dω_in| = η²·cos θin / cos θout; 0 for
// a direction into the medium or one the plane reflects totally.
double exit_guide_pdf(const RenderScene& scene, const ExitGuide& guide, const Vec3& wi);
// A direction drawn from it (the map's sample carried back through the plane), or none.
std::optional<Vec3> sample_exit_guide(const RenderScene& scene, const ExitGuide& guide, double u1, double u2);
// The connection itself at a camera walk's medium vertex (direct_light.h: MediumPoint): what
// reaches the map along a direction drawn from the guide, through at least one smooth interface,
// MIS-weighted against the phase function's direction; zero where it meets any other surface.
// It stops where the walk would (`through`).
template <std::size_t N>
SampledSpectrum<N> environment_through_interfaces(const SceneView<N>& v, const MediumPoint& at, const ExitGuide& guide,
                                                  const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays,
                                                  ThroughInterfaces through);

}  // namespace bouguer
