// Next-event estimation through one smooth interface (integrators/manifold.h). A flat one: a point lamp under a flat
// water surface lights a diffuse ceiling above it only along refracted paths, which the path tracer
// now reaches by solving Snell's law on the plane. The closed form: a ray leaving the lamp (depth d)
// at α from the vertical meets the surface at d·tan α, leaves at β (sin β = n·sin α) and meets the
// ceiling (height h) at R(α) = d·tan α + h·tan β; the ray tube gives the ceiling the irradiance
//   E(R) = T(α)·I·sin α / (R·dR/dα),   dR/dα = d/cos²α + h·n·cos α/cos³β,
// T the Fresnel transmittance from water to air, so the ceiling of reflectance ρ shows ρ·E/π (on
// the axis: T·I/(d + n·h)², the lamp's image at the apparent depth d/n). That is the direct light
// (max_depth 1): beyond it the ceiling also sees itself in the water (R ≈ 2 %: the mean read
// 1.005 with it, pixels up to 6 % off with its noise), and light reflected inside the water.
#include <gtest/gtest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <algorithm>
#include <numbers>
#include <optional>
#include <type_traits>
#include <vector>

#include "bouguer/core/frame.h"
#include "bouguer/core/rng.h"
#include "bouguer/integrators/manifold.h"
#include "bouguer/integrators/manifold_chain.h"
#include "bouguer/render/camera.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "bouguer/materials/fresnel.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr double kDepth_m = 0.05, kCeiling_m = 0.1, kN = 1.33, kRho = 0.8, kScale = 0.01, kView_m = 0.12;
constexpr int kPixels = 16;

// The water: a box (its top a face of a mesh), or an exact cylinder scaled unevenly into an
// elliptic one 1 by 1.5 m across and 0.2 m deep (its top cap, still a plane).
constexpr const char* kWaterBox =
    R"({"type": "box", "size": [2, 0.2, 2]}, "transform": [{"translate": [0, -0.1, 0]}])";
constexpr const char* kWaterCylinder =
    R"({"type": "cylinder", "radius": 0.5, "height": 0.4},
        "transform": [{"scale": [2, 0.5, 3]}, {"translate": [0, -0.2, 0]}])";

std::string water_scene(const char* integrator, int spp, const char* water = kWaterBox) {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0.05, 0], "look_at": [0, 1, 0], "up": [0, 0, -1],
               "width": {}, "resolution": [{}, {}]}},
    "render": {{"integrator": "{}", "spectral": "full", "spp": {}, "max_depth": 1, "seed": 5}},
    "world_medium": "vacuum",
    "media": {{"water": {{"ior": {}}}}},
    "objects": [
      {{"name": "water", "shape": {}, "inside": "water"}},
      {{"name": "ceiling", "shape": {{"type": "quad", "size": [0.4, 0.4]}},
        "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [0, {}, 0]}}],
        "material": {{"type": "diffuse", "reflectance": {}}}}}
    ],
    "lights": [{{"type": "point", "position": [0, {}, 0], "spectrum": "D65", "scale": {}}}],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                     kView_m, kPixels, kPixels, integrator, spp, kN, water, kCeiling_m, kRho, -kDepth_m, kScale);
}

// The ceiling's radiance at distance r from the axis (D65 at Y = 1 is linear sRGB (1, 1, 1)).
double ceiling_radiance(double r) {
  auto reach = [](double a) {
    const double sin_b = kN * std::sin(a);
    return kDepth_m * std::tan(a) + kCeiling_m * sin_b / std::sqrt(1.0 - sin_b * sin_b);
  };
  double lo = 0.0, hi = std::asin(1.0 / kN) * (1.0 - 1e-9);
  for (int i = 0; i < 200; ++i) ((reach(0.5 * (lo + hi)) < r) ? lo : hi) = 0.5 * (lo + hi);
  const double a = 0.5 * (lo + hi), sin_b = kN * std::sin(a), cos_b = std::sqrt(1.0 - sin_b * sin_b);
  const double cos_a = std::cos(a);
  const double dr = kDepth_m / (cos_a * cos_a) + kCeiling_m * kN * cos_a / (cos_b * cos_b * cos_b);
  const double t = 1.0 - fresnel_dielectric(cos_a, cos_b, kN, 1.0);
  const double e = r > 1e-12 ? t * kScale * std::sin(a) / (r * dr)
                             : t * kScale / ((kDepth_m + kN * kCeiling_m) * (kDepth_m + kN * kCeiling_m));
  return kRho * e / std::numbers::pi;
}

// The ceiling's pixels over the closed form `radiance(r)` averaged over each pixel's footprint
// (8 × 8 points): the mean ratio and the worst pixel's distance from 1.
struct CeilingRatio {
  double mean = 0.0, worst = 0.0;
};
// The closed form `radiance(r)` (of the distance from the axis) or `radiance(x, z)` averaged over
// pixel (i, j)'s footprint (8 × 8 points) of an orthographic view `view_m` wide and `pixels`
// across, centred on the axis.
template <typename Radiance>
double footprint_mean(Radiance radiance, double view_m, int pixels, int i, int j) {
  const double pixel_m = view_m / pixels;
  double sum = 0.0;
  constexpr int kSub = 8;
  for (int a = 0; a < kSub; ++a)
    for (int b = 0; b < kSub; ++b) {
      const double x = -0.5 * view_m + (i + (a + 0.5) / kSub) * pixel_m;
      const double z = -0.5 * view_m + (j + (b + 0.5) / kSub) * pixel_m;
      if constexpr (std::is_invocable_v<Radiance, double, double>)
        sum += radiance(x, z);
      else
        sum += radiance(std::hypot(x, z));
    }
  return sum / (kSub * kSub);
}
template <typename Radiance>
CeilingRatio ceiling_ratio(const Film& film, Radiance radiance) {
  CeilingRatio r;
  for (int j = 0; j < kPixels; ++j)
    for (int i = 0; i < kPixels; ++i) {
      const double expected = footprint_mean(radiance, kView_m, kPixels, i, j);
      for (int c = 0; c < 3; ++c) {
        const double ratio = film.rgb_at(i, j)[c] / expected;
        r.worst = std::max(r.worst, std::abs(ratio - 1.0));
        r.mean += ratio / (3.0 * kPixels * kPixels);
      }
    }
  return r;
}

// Every pixel within 0.3 % of the closed form averaged over its footprint (8 × 8 points), and
// their mean within 0.05 %: the path tracer's next-event estimation of a point lamp draws no
// random number but the pixel position (64 jittered strata), so only the footprint's variation
// is left. A missing Fresnel factor (2 % on the axis), a radiance scaled by n² across the surface
// (77 %), a ray tube taken at the straight line's distance (the lamp's image at depth d instead of
// d/n: 27 % on the axis) or no light at all (before: the shadow ray stopped at the water) fails.
// The same with the water an exact cylinder, its surface the top cap (a plane under any affine
// transform): before, a shadow ray stopped by a cylinder had no solve, and the ceiling was black.
TEST(ManifoldNextEvent, PointLampUnderFlatWaterLightsTheCeilingAsTheClosedFormSays) {
  for (const auto& [water, what] : {std::pair{kWaterBox, "a box's face"}, std::pair{kWaterCylinder, "a cylinder's cap"}}) {
    const Film film = test::render_text(water_scene("path", 64, water));
    const auto [mean, worst] = ceiling_ratio(film, ceiling_radiance);
    std::printf("point lamp under flat water (%s): ceiling / closed form, mean %.5f, worst pixel %.2e (axis %.4g)\n",
                what, mean, worst, ceiling_radiance(0.0));
    EXPECT_LT(worst, 0.003) << what;
    EXPECT_NEAR(mean, 1.0, 0.0005) << what;
  }
}

// Water of index kN (`water`: kWaterBox, kWaterCylinder or another shape) in vacuum, lit by
// `lights` (the JSON array's entries), `more` added to its objects (a leading comma), no
// background: compiled.
RenderScene water_with(const char* water, const std::string& lights, const char* more = "") {
  return compile(parse_scene(fmt::format(R"({{
    "camera": {{"position": [0, 1, 1], "look_at": [0, 0, 0], "resolution": [4, 4]}},
    "render": {{"integrator": "path", "spectral": "hero", "spp": 1}},
    "world_medium": "vacuum",
    "media": {{"water": {{"ior": {}}}}},
    "objects": [{{"name": "water", "shape": {}, "inside": "water"}}{}],
    "lights": [{}],
    "background": {{"spectrum": "E", "scale": 0}}
  }})", kN, water, more, lights), "water_with.json"));
}

// A medium point at x inside the scene's first object (its contents, its nested bit), the walk
// having arrived going down.
MediumPoint in_first_object(const RenderScene& scene, const Vec3& x, const PhaseFunction& phase) {
  const Surface& s = scene.surfaces[0];
  return MediumPoint{x, Vec3{0, -1, 0}, phase, s.medium_behind, s.nested >= 0 ? nested_bit(s.nested) : InsideSet{0}};
}

// Next-event estimation at a medium point `at` of `scene` (the path tracer's, through the
// interfaces, those connections made with probability `share`; area lamps through chains), at the
// hero wavelengths 0.3 of the way along the spectrum, from `rng`; `after`: the stream's next
// number once it is done.
SampledSpectrum<kHeroCount> next_event_at(const RenderScene& scene, const MediumPoint& at, Rng rng,
                                          double share = 1.0, std::uint32_t* after = nullptr) {
  const SpectralTables<kHeroCount> tables(scene.spectra, SpectralMode::hero);
  const Camera camera(scene.camera);
  SceneView<kHeroCount> v{scene, tables, camera, 8};
  v.area_lamp_chains = true;
  const SampledWavelengths<kHeroCount> w = tables.wavelengths(0.3);
  std::uint64_t rays = 0;
  const SampledSpectrum<kHeroCount> l =
      direct_light_in_medium(v, at, w, SampledSpectrum<kHeroCount>::constant(1.0f), rng, rays, true, share);
  if (after) *after = rng.next_u32();
  return l;
}

// What next-event estimation at `at` gets from the scene's one distant lamp, over the lamp's
// irradiance, at each hero wavelength.
std::array<double, kHeroCount> sun_at(const RenderScene& scene, const MediumPoint& at) {
  const SpectralTables<kHeroCount> tables(scene.spectra, SpectralMode::hero);
  const SampledSpectrum<kHeroCount> sun =
      tables.at(std::get<DistantLight>(scene.lights[0]).irradiance, tables.wavelengths(0.3));
  const SampledSpectrum<kHeroCount> l = next_event_at(scene, at, Rng(1, 2));
  std::array<double, kHeroCount> out{};
  for (std::size_t k = 0; k < kHeroCount; ++k) out[k] = l[k] / sun[k];
  return out;
}

// A sun through the flat top of the water (a box's face, a cylinder's cap) at a vertex in the
// water (manifold.h: distant_light_through_chains for the box's face, distant_light_through_plane
// for the cap): next-event estimation at a medium point gets
// E·T·cos θ_l/cos θ_x times the phase function's value at every carried wavelength, to rounding,
// for the sun at 0°, 40° and 70° from the vertical, at two depths (a sun's light does not fall
// off), isotropic and Henyey–Greenstein g = 0.5 (the light travelling down the refracted line,
// scattered back up the walk: cos θ = −cos θ_x, the phase small where the other convention
// would make it large). What it catches: the beam's compression left out (cos θ_l/cos θ_x: 14 %
// bright at 40°, 107 % at 70°), a radiance's n² (77 %), no Fresnel (2 % to 14 %), the phase
// function read the other way (a factor 7 to 27 at g = 0.5), the crossing or the direction on the
// water's side wrong (the face missed: nothing), and no light at all (before: the glass stopped it).
TEST(ManifoldNextEvent, SunThroughFlatWaterIsTheClosedForm) {
  for (const auto& [water, what] : {std::pair{kWaterBox, "a box's face"}, std::pair{kWaterCylinder, "a cylinder's cap"}})
    for (const double theta_deg : {0.0, 40.0, 70.0}) {
      const double theta = theta_deg * std::numbers::pi / 180.0;
      const RenderScene scene = water_with(
          water, fmt::format(R"({{"type": "distant", "direction": [{}, {}, 0], "spectrum": "D65", "scale": 1}})",
                             std::sin(theta), -std::cos(theta)));
      ASSERT_GE(scene.surfaces[0].medium_behind, 0);
      const double cos_x = std::sqrt(1.0 - std::pow(std::sin(theta) / kN, 2.0));
      const double t = 1.0 - fresnel_dielectric(std::cos(theta), cos_x, 1.0, kN);
      for (const double g : {0.0, 0.5}) {
        const PhaseFunction phase = g == 0.0 ? PhaseFunction{IsotropicPhase{}} : PhaseFunction{HenyeyGreensteinPhase{g}};
        const double hg = (1.0 - g * g) / (4.0 * std::numbers::pi * std::pow(1.0 + g * g + 2.0 * g * cos_x, 1.5));
        const double expected = t * std::cos(theta) / cos_x * hg;
        for (const double depth_m : {0.01, 0.15}) {
          const auto l = sun_at(scene, in_first_object(scene, Vec3{0.02, -depth_m, -0.03}, phase));
          std::printf("sun through %s, %.0f deg, g %.1f, %.0f mm deep: closed form %.6f, found %.6f (over E)\n", what,
                      theta_deg, g, depth_m * 1e3, expected, l[0]);
          for (std::size_t k = 0; k < kHeroCount; ++k)
            EXPECT_NEAR(l[k], expected, 1e-6 * expected)
                << what << ", " << theta_deg << " deg, g " << g << ", " << depth_m << " m, " << k;
        }
      }
    }
}

// A sun over water under a floating pane of absorbing glass (σ_a 20 per m, 10 mm thick, 10 mm of
// air between: three flat crossings, the chain's, manifold_chain.h: solve_chain_towards), at a
// point in the water: E times the three Fresnel transmittances, the glass's exp(−σ_a·t/cos θ_g)
// and the beam's compression, which through parallel planes is the product of each plane's
// cos θ_in/cos θ_out, cos θ_air/cos θ_water, times the isotropic phase 1/4π, to 2e-5 (measured
// 2e-9 to 7e-6: float spectra). Sun at 0°,
// 40° and 70° from the vertical. What it catches: the beam tube of the straight line or of one
// plane (14 % at 40°, 107 % at 70°), a Fresnel factor left out (4 % to 25 %), the glass's chord
// taken as its thickness (4 % at 70°), a radiance's n², no light at all (before: a sun through
// more than one crossing was left out).
TEST(ManifoldNextEvent, SunThroughFlatLayersIsTheClosedForm) {
  constexpr double kGlass = 1.5, kSigma = 20.0, kPane_m = 0.01;
  for (const double theta_deg : {0.0, 40.0, 70.0}) {
    const double theta = theta_deg * std::numbers::pi / 180.0;
    const RenderScene scene = compile(parse_scene(fmt::format(R"({{
      "camera": {{"position": [0, 1, 1], "look_at": [0, 0, 0], "resolution": [4, 4]}},
      "render": {{"integrator": "path", "spectral": "hero", "spp": 1}},
      "world_medium": "vacuum",
      "media": {{"water": {{"ior": {}}},
                "glass": {{"ior": {}, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [380, 780],
                                                     "value": [{}, {}]}}}}}},
      "objects": [
        {{"name": "water", "shape": {}, "inside": "water"}},
        {{"name": "pane", "shape": {{"type": "box", "size": [2, {}, 2]}}, "transform": [{{"translate": [0, 0.015, 0]}}],
         "inside": "glass"}}
      ],
      "lights": [{{"type": "distant", "direction": [{}, {}, 0], "spectrum": "D65", "scale": 1}}],
      "background": {{"spectrum": "E", "scale": 0}}
    }})", kN, kGlass, kSigma, kSigma, kWaterBox, kPane_m, std::sin(theta), -std::cos(theta)), "sun_over_pane.json"));
    ASSERT_GE(scene.surfaces[0].medium_behind, 0);
    const double sin_a = std::sin(theta), cos_a = std::cos(theta);
    const double cos_g = std::sqrt(1.0 - std::pow(sin_a / kGlass, 2.0)), cos_w = std::sqrt(1.0 - std::pow(sin_a / kN, 2.0));
    const double t = (1.0 - fresnel_dielectric(cos_a, cos_g, 1.0, kGlass)) *
                     (1.0 - fresnel_dielectric(cos_g, cos_a, kGlass, 1.0)) * (1.0 - fresnel_dielectric(cos_a, cos_w, 1.0, kN));
    const double expected = t * std::exp(-kSigma * kPane_m / cos_g) * cos_a / cos_w / (4.0 * std::numbers::pi);
    const auto l = sun_at(scene, in_first_object(scene, Vec3{0.02, -0.03, -0.01}, PhaseFunction{IsotropicPhase{}}));
    std::printf("sun through a pane over water, %.0f deg: closed form %.7f, found %.7f (over E), %.1e off\n", theta_deg,
                expected, l[0], l[0] / expected - 1.0);
    for (std::size_t k = 0; k < kHeroCount; ++k) EXPECT_NEAR(l[k], expected, 2e-5 * expected) << theta_deg << " deg, " << k;
  }
}

// A split walk's connections through the interfaces, thinned (dense_media.h: split_walk_nee_share),
// from direct_light_in_medium at a point in water with a point lamp in the same water (a shadow
// ray: S) and a lamp beyond the water's surface (T). Through a box's face (a chain: a sun) and an
// exact ball's surface (a caster: a point lamp), where T draws no number: each lamp alone and
// together, S + T; made with a share s of 1/4, each of 2000 draws is S (not made) or S + T/s, to
// float rounding, and the draws that make it number 2000·s within 4 standard deviations of the
// binomial. A small area lamp above the box's face (through a chain from the point drawn on it):
// the mean of 4000 draws with the share the mean of 4000 without, within 4 standard errors. A
// scene without lamps draws no number for it (the stream after the call the same). What it
// catches: a connection through the interfaces not divided by the share (S + T), the straight one
// divided too (S/s) or thinned with it (0), the share ignored (every draw S + T), a route (caster,
// chain, area lamp's chain) left out of the thinning or its division, and a number drawn where
// nothing can be thinned (the images lit by a map alone would all change).
TEST(ManifoldNextEvent, ConnectionsThroughTheInterfacesThinnedKeepTheirExpectation) {
  constexpr const char* kBall = R"({"type": "sphere", "radius": 0.2})";
  constexpr const char* kInside = R"({"type": "point", "position": [0.05, -0.04, 0], "spectrum": "D65", "scale": 0.001})";
  // What the connections bring at the first hero wavelength at a point in the water, from stream
  // `stream`; `after`: the stream's next number once they are made.
  auto light_at = [](const RenderScene& scene, double share, std::uint64_t stream, std::uint32_t* after = nullptr) {
    const MediumPoint at = in_first_object(scene, Vec3{0.02, -0.05, -0.03}, PhaseFunction{IsotropicPhase{}});
    return static_cast<double>(next_event_at(scene, at, Rng(7, stream), share, after)[0]);
  };
  constexpr double kShare = 0.25;
  for (const auto& [water, beyond, what] :
       {std::tuple{kWaterBox, R"({"type": "distant", "direction": [0.64, -0.77, 0], "spectrum": "D65", "scale": 1})",
                   "a sun through a box's face"},
        std::tuple{kBall, R"({"type": "point", "position": [0.1, 0.3, 0], "spectrum": "D65", "scale": 0.01})",
                   "a point lamp through an exact ball"}}) {
    const RenderScene lamp = water_with(water, kInside), far = water_with(water, beyond),
                      both = water_with(water, fmt::format("{}, {}", kInside, beyond));
    ASSERT_GE(both.surfaces[0].medium_behind, 0);
    const double straight = light_at(lamp, 1.0, 0), through = light_at(far, 1.0, 0);
    ASSERT_GT(straight, 0.0) << what;
    ASSERT_GT(through, 0.0) << what;
    EXPECT_NEAR(light_at(both, 1.0, 0), straight + through, 1e-5 * (straight + through)) << what;
    constexpr int kDraws = 2000;
    int made = 0;
    for (int i = 0; i < kDraws; ++i) {
      const double l = light_at(both, kShare, static_cast<std::uint64_t>(i));
      const bool with = std::abs(l - (straight + through / kShare)) <= 1e-5 * (straight + through / kShare);
      EXPECT_TRUE(with || std::abs(l - straight) <= 1e-5 * straight) << what << ", draw " << i << ": " << l;
      made += with;
    }
    std::printf("thinned connections, %s: S %.6g, T %.6g; made %d of %d (share %.2f)\n", what, straight, through,
                made, kDraws, kShare);
    EXPECT_NEAR(made, kDraws * kShare, 4.0 * std::sqrt(kDraws * kShare * (1.0 - kShare))) << what;
  }
  {  // an area lamp through the box's face
    const RenderScene scene = water_with(kWaterBox, kInside, R"(, {"name": "panel", "shape": {"type": "quad",
      "size": [0.04, 0.04]}, "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0.15, 0.25, 0]}],
      "emission": {"spectrum": "D65", "scale": 50}})");
    constexpr int kDraws = 4000;
    std::array<test::Estimate, 2> e;
    for (const double share : {1.0, kShare}) {
      std::vector<double> l;
      for (int i = 0; i < kDraws; ++i) l.push_back(light_at(scene, share, static_cast<std::uint64_t>(100000 + i)));
      e[share < 1.0] = test::mean_estimate(l);
    }
    const double straight = light_at(water_with(kWaterBox, kInside), 1.0, 0);
    const double se = std::hypot(e[0].standard_error, e[1].standard_error);
    std::printf("an area lamp through a box's face: %.6g ± %.2g whole, %.6g ± %.2g thinned (the lamp in the water "
                "alone %.6g)\n", e[0].mean, e[0].standard_error, e[1].mean, e[1].standard_error, straight);
    EXPECT_GT(e[0].mean, 1.2 * straight) << "the panel's light through the face is not resolved";
    EXPECT_NEAR(e[1].mean, e[0].mean, 4.0 * se);
  }
  {  // without lamps: no number drawn
    const RenderScene scene = water_with(kWaterBox, "");
    std::uint32_t whole = 0, thinned = 0;
    light_at(scene, 1.0, 3, &whole);
    light_at(scene, kShare, 3, &thinned);
    EXPECT_EQ(whole, thinned) << "a number drawn to thin connections in a scene without lamps";
  }
}

// A sun through a clear glass ball (n 1.5, σ_a 10 per m, radius R = 20 mm, an exact sphere: a
// caster), traced forward in the plane through the ball's centre along the sun and the point: a ray
// of the sun's beam at signed height h from that axis refracts in (and, for a point beyond the
// ball, out) and meets the plane across the axis through the point at signed distance ρ(h); the
// beam of the rings h..h+dh reaches the rings ρ..ρ+dρ, so each path (each root of ρ(h) = ρ_x)
// brings the irradiance across the beam E·T·|h|/(ρ_x·|dρ/dh|)/cos γ (γ its final direction's angle
// from the axis; T its Fresnel transmittances and exp(−σ_a·chord)). At the centre, the paraxial
// limit (n_in/n_out)²·T(0). Independent of the solve it checks (sphere_refraction_towards,
// sphere_passage_towards and beam_tube solve backwards from the point; this traces forwards from
// the sun over 4000 heights), to 1e-4 (beam_tube's differences). What it catches: the sphere's
// lens left out of the tube (a factor 2.25 at the centre), the out-of-plane factor ρ_y/ρ_x
// (tens of %), a path of two (inside the caustic) missed, Fresnel, the chord's absorption.
namespace {

struct BallPath {
  bool valid = false;
  double rho = 0.0, cos_gamma = 0.0, transmittance = 0.0;
};
// The ray at height h (in radii of 1: R = 1, so the point's plane u is in radii too) traced
// through the ball to the plane at u (along the sun's travel from the centre); `inside`: the plane
// is met inside the ball, before the exit.
BallPath trace_ball(double h, double u, bool inside, double n, double sigma_r) {
  BallPath p;
  const double u1 = -std::sqrt(1.0 - h * h);  // the entry point (h, u1); the ray travels along +u
  const double cos_i = -u1, cos_t = std::sqrt(1.0 - (1.0 - cos_i * cos_i) / (n * n));
  // Refracted in: t = d/n + (cos_i/n − cos_t)·normal, the normal (h, u1) outward.
  const double k = cos_i / n - cos_t;
  const double tv = k * h, tu = 1.0 / n + k * u1;
  const double t_in = 1.0 - fresnel_dielectric(cos_i, cos_t, 1.0, n);
  if (inside) {
    const double s = (u - u1) / tu;
    const double v = h + s * tv, w = u;
    if (!(s > 0.0) || v * v + w * w >= 1.0) return p;
    return {true, v, tu, t_in * std::exp(-sigma_r * s)};
  }
  const double chord = -2.0 * (h * tv + u1 * tu);
  const double v2 = h + chord * tv, u2 = u1 + chord * tu;  // the exit point, its outward normal itself
  const double cos_o = tv * v2 + tu * u2, sin2 = n * n * (1.0 - cos_o * cos_o);
  if (sin2 >= 1.0) return p;
  const double cos_x = std::sqrt(1.0 - sin2), m = n * cos_o - cos_x;
  const double ov = n * tv - m * v2, ou = n * tu - m * u2;
  const double s = (u - u2) / ou;
  if (!(s > 0.0)) return p;
  return {true, v2 + s * ov, ou,
          t_in * (1.0 - fresnel_dielectric(cos_o, cos_x, n, 1.0)) * std::exp(-sigma_r * chord)};
}

// The irradiance across the beam over E at a point at u along the axis and rho_x > 0 from it.
double ball_irradiance(double rho_x, double u, bool inside, double n, double sigma_r, int* paths) {
  constexpr int kHeights = 4000;
  auto miss = [&](double h) {
    const BallPath p = trace_ball(h, u, inside, n, sigma_r);
    return p.valid ? p.rho - rho_x : std::numeric_limits<double>::quiet_NaN();
  };
  double sum = 0.0;
  *paths = 0;
  for (int i = 0; i < kHeights; ++i) {
    double lo = -1.0 + 2.0 * (i + 1e-9) / kHeights, hi = -1.0 + 2.0 * (i + 1.0 - 1e-9) / kHeights;
    double m_lo = miss(lo), m_hi = miss(hi);
    if (!(m_lo * m_hi < 0.0)) continue;
    for (int b = 0; b < 200 && hi - lo > 1e-15; ++b) {
      const double mid = 0.5 * (lo + hi), m_mid = miss(mid);
      ((m_mid < 0.0) == (m_lo < 0.0) ? lo : hi) = mid;
      if ((m_mid < 0.0) == (m_lo < 0.0)) m_lo = m_mid;
    }
    const double h = 0.5 * (lo + hi), dh = 1e-7;
    const BallPath p = trace_ball(h, u, inside, n, sigma_r);
    const double drho = (trace_ball(h + dh, u, inside, n, sigma_r).rho - trace_ball(h - dh, u, inside, n, sigma_r).rho) / (2.0 * dh);
    sum += p.transmittance * std::abs(h) / (rho_x * std::abs(drho)) / p.cos_gamma;
    ++*paths;
  }
  return sum;
}

}  // namespace

TEST(ManifoldNextEvent, SunThroughAGlassBallIsTheForwardTracedClosedForm) {
  constexpr double kR = 0.02, kGlass = 1.5, kSigma = 10.0;
  for (const double theta_deg : {0.0, 30.0}) {
    const double theta = theta_deg * std::numbers::pi / 180.0;
    const Vec3 travel{std::sin(theta), -std::cos(theta), 0.0};
    const RenderScene scene = compile(parse_scene(fmt::format(R"({{
      "camera": {{"position": [0, 1, 1], "look_at": [0, 0, 0], "resolution": [4, 4]}},
      "render": {{"integrator": "path", "spectral": "hero", "spp": 1}},
      "world_medium": "vacuum",
      "media": {{"glass": {{"ior": {}, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [380, 780],
                                                     "value": [{}, {}]}}}}}},
      "objects": [{{"name": "ball", "shape": {{"type": "sphere", "radius": {}}}, "inside": "glass"}}],
      "lights": [{{"type": "distant", "direction": [{}, {}, 0], "spectrum": "D65", "scale": 1}}],
      "background": {{"spectrum": "E", "scale": 0}}
    }})", kGlass, kSigma, kSigma, kR, travel.x, travel.y), "sun_over_ball.json"));
    ASSERT_EQ(scene.casters.size(), 1u);
    const Frame frame(travel);  // s, t across the sun's travel
    // Points inside (in radii: along the travel, across it) and beyond the ball, in its shadow.
    struct Case {
      double u, across, turn;
      bool inside;
    };
    for (const Case c : {Case{0.0, 0.0, 0.0, true}, Case{0.3, 0.4, 0.7, true}, Case{-0.5, 0.2, 2.0, true},
                         Case{0.5, 0.35, -1.0, true}, Case{1.2, 0.05, 0.5, false}, Case{1.1, 0.1, 0.5, false},
                         Case{3.0, 0.1, 0.3, false}, Case{3.0, 0.45, 1.2, false},
                         Case{2.2, 0.3, -2.5, false}, Case{5.0, 0.8, 0.0, false}}) {
      const Vec3 across = frame.s * std::cos(c.turn) + frame.t * std::sin(c.turn);
      const Vec3 x = (travel * c.u + across * c.across) * kR;
      const Surface& ball = scene.surfaces[0];
      const int medium = c.inside ? ball.medium_behind : ball.medium_front;
      const MediumPoint at{x, Vec3{0, -1, 0}, PhaseFunction{IsotropicPhase{}}, medium,
                           c.inside && ball.nested >= 0 ? nested_bit(ball.nested) : InsideSet{0}};
      int paths = 1;
      const double e = c.across == 0.0 ? kGlass * kGlass * (1.0 - fresnel_dielectric(1.0, 1.0, 1.0, kGlass)) *
                                             std::exp(-kSigma * kR)
                                       : ball_irradiance(c.across, c.u, c.inside, kGlass, kSigma * kR, &paths);
      const double expected = e / (4.0 * std::numbers::pi);
      const auto l = sun_at(scene, at);
      std::printf("sun through a glass ball, %.0f deg, point at (%.1f, %.2f) radii %s: %d path(s), closed form %.7f, "
                  "found %.7f (over E)\n",
                  theta_deg, c.u, c.across, c.inside ? "inside" : "beyond", paths, expected, l[0]);
      EXPECT_GT(paths, 0);
      for (std::size_t k = 0; k < kHeroCount; ++k)
        EXPECT_NEAR(l[k], expected, 1e-4 * expected) << theta_deg << " deg, (" << c.u << ", " << c.across << "), " << k;
    }
  }
}

// Flat layers between a point lamp and the ceiling (each a thickness and an index, from the lamp
// up): a ray leaving the lamp at α₀ from the vertical crosses layer i at θᵢ (nᵢ sin θᵢ = n₀ sin α₀)
// and meets the ceiling at R = Σ tᵢ tan θᵢ, dR/dα₀ = Σ tᵢ·n₀ cos α₀/(nᵢ cos³θᵢ); each interface
// passes its Fresnel transmittance, so the ceiling's irradiance is E = T·I·sin α₀/(R·dR/dα₀) (on
// the axis T·I/(Σ tᵢ·n₀/nᵢ)²), its radiance ρE/π.
struct Layer {
  double thickness_m, n;
};
double layered_ceiling_radiance(const std::vector<Layer>& layers, double r) {
  const double n0 = layers[0].n;
  double n_min = n0;
  for (const Layer& l : layers) n_min = std::min(n_min, l.n);
  struct At {
    double reach, dreach, transmittance;
  };
  auto at = [&](double a) {
    At o{0.0, 0.0, 1.0};
    double cos_before = std::cos(a);
    for (std::size_t i = 0; i < layers.size(); ++i) {
      const double sin_t = n0 * std::sin(a) / layers[i].n, cos_t = std::sqrt(1.0 - sin_t * sin_t);
      o.reach += layers[i].thickness_m * sin_t / cos_t;
      o.dreach += layers[i].thickness_m * n0 * std::cos(a) / (layers[i].n * cos_t * cos_t * cos_t);
      if (i > 0) o.transmittance *= 1.0 - fresnel_dielectric(cos_before, cos_t, layers[i - 1].n, layers[i].n);
      cos_before = cos_t;
    }
    return o;
  };
  if (r < 1e-12) {
    double depth = 0.0;
    for (const Layer& l : layers) depth += l.thickness_m * n0 / l.n;
    return kRho * at(0.0).transmittance * kScale / (depth * depth) / std::numbers::pi;
  }
  double lo = 0.0, hi = std::asin(n_min / n0) * (1.0 - 1e-9);
  for (int i = 0; i < 200; ++i) ((at(0.5 * (lo + hi)).reach < r) ? lo : hi) = 0.5 * (lo + hi);
  const double a = 0.5 * (lo + hi);
  const At o = at(a);
  return kRho * o.transmittance * kScale * std::sin(a) / (r * o.dreach) / std::numbers::pi;
}

// A point lamp under flat layers (boxes 2 m wide) lights the ceiling as the layered closed form
// says: the chain of crossings (manifold_chain.h) solved by Newton, where one flat face has its
// own exact solve. A glass pane 20 mm thick in vacuum, the lamp 50 mm below (two crossings), and a
// lamp 30 mm deep in water under 10 mm of air and a 10 mm pane of n = 1.5 (three crossings, the
// lamp's index not the ceiling's: the ray tube's (η_x/η_q)² is 0.57 there). Every pixel within
// 0.3 % of the closed form averaged over its footprint, the mean within 0.05 % (the path tracer
// draws no random number here but the pixel position). Before: black (a shadow ray met more than
// one face); without Fresnel at one crossing about 4 % bright, without the index ratio 77 %. And a
// 2 mm pane 30 m from the origin, where rounding is 300 times coarser: before Newton's tolerance
// and the crossings' window followed the coordinates' rounding, the ceiling read 0.63 of the
// closed form there, pixels 56 % off.
TEST(ManifoldNextEvent, PointLampUnderFlatLayersLightsTheCeilingAsTheClosedFormSays) {
  struct Case {
    const char* what;
    std::string objects;
    double lamp_y;
    std::vector<Layer> layers;
    double x_m = 0.0;  // the whole scene moved along x
  };
  const std::vector<Case> cases{
      {"a glass pane",
       R"({"name": "pane", "shape": {"type": "box", "size": [2, 0.02, 2]}, "transform": [{"translate": [0, 0.01, 0]}],
           "inside": "glass"})",
       -0.05, {{0.05, 1.0}, {0.02, 1.5}, {kCeiling_m - 0.02, 1.0}}},
      {"water, air and a pane",
       R"({"name": "water", "shape": {"type": "box", "size": [2, 0.2, 2]}, "transform": [{"translate": [0, -0.1, 0]}],
           "inside": "water"},
          {"name": "pane", "shape": {"type": "box", "size": [2, 0.01, 2]}, "transform": [{"translate": [0, 0.015, 0]}],
           "inside": "glass"})",
       -0.03, {{0.03, kN}, {0.01, 1.0}, {0.01, 1.5}, {kCeiling_m - 0.02, 1.0}}},
      {"water above, the ceiling in it",
       R"({"name": "water", "shape": {"type": "box", "size": [2, 0.2, 2]}, "transform": [{"translate": [0, 0.1, 0]}],
           "inside": "water"})",
       -0.05, {{0.05, 1.0}, {kCeiling_m, kN}}},
      {"a 2 mm pane 30 m from the origin",
       R"({"name": "pane", "shape": {"type": "box", "size": [2, 0.002, 2]}, "transform": [{"translate": [30, 0.001, 0]}],
           "inside": "glass"})",
       -0.05, {{0.05, 1.0}, {0.002, 1.5}, {kCeiling_m - 0.002, 1.0}}, 30.0},
  };
  for (const Case& c : cases) {
    const Film film = test::render_text(fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [{7}, 0.05, 0], "look_at": [{7}, 1, 0], "up": [0, 0, -1],
                 "width": {0}, "resolution": [{1}, {1}]}},
      "render": {{"integrator": "path", "spectral": "full", "spp": 64, "max_depth": 1, "seed": 5}},
      "world_medium": "vacuum",
      "media": {{"water": {{"ior": {2}}}, "glass": {{"ior": 1.5}}}},
      "objects": [{3},
        {{"name": "ceiling", "shape": {{"type": "quad", "size": [0.4, 0.4]}},
          "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [{7}, {4}, 0]}}],
          "material": {{"type": "diffuse", "reflectance": {5}}}}}],
      "lights": [{{"type": "point", "position": [{7}, {6}, 0], "spectrum": "D65", "scale": {8}}}],
      "background": {{"spectrum": "E", "scale": 0}}
    }})",
                                                    kView_m, kPixels, kN, c.objects, kCeiling_m, kRho, c.lamp_y, c.x_m,
                                                    kScale));
    const auto [mean, worst] = ceiling_ratio(film, [&](double r) { return layered_ceiling_radiance(c.layers, r); });
    std::printf("point lamp under %s: ceiling / closed form, mean %.5f, worst pixel %.2e (axis %.4g)\n", c.what, mean,
                worst, layered_ceiling_radiance(c.layers, 0.0));
    EXPECT_LT(worst, 0.003) << c.what;
    EXPECT_NEAR(mean, 1.0, 0.0005) << c.what;
  }
}

// A flat face whose straight segment to the lamp the chain cannot seed (an opaque ball on it, in
// the water, away from the refracted path) is left to the face's own exact solve (manifold.h:
// delta_light_through_interface), which finds the refracted path past the ball. A lamp 50 mm deep,
// the ceiling 20 mm above the water, the two pixels 100 mm off the axis (refracted at about 44°
// in the water, their straight segments 18 mm from their refracted paths where the balls sit, 10 mm
// under the surface): each within 0.5 % of the closed form. With the fallback planted away (no
// chain, no light), both read 0.
TEST(ManifoldNextEvent, AFlatFaceTheChainCannotSeedIsSolvedExactly) {
  constexpr double d = 0.05, h = 0.02, view = 0.25, x_ball = 0.1 * (d - 0.01) / (d + h);
  constexpr int pixels = 31;
  const Film film = test::render_text(fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0.01, 0], "look_at": [0, 1, 0], "up": [0, 0, -1],
               "width": {0}, "resolution": [{1}, {1}]}},
    "render": {{"integrator": "path", "spectral": "hero", "spp": 16, "max_depth": 1, "seed": 5}},
    "world_medium": "vacuum",
    "media": {{"water": {{"ior": {2}}}}},
    "objects": [
      {{"name": "water", "shape": {{"type": "box", "size": [2, 0.2, 2]}}, "transform": [{{"translate": [0, -0.1, 0]}}],
        "inside": "water"}},
      {{"name": "left", "shape": {{"type": "sphere", "radius": "8 mm"}}, "transform": [{{"translate": [{3}, -0.01, 0]}}],
        "material": {{"type": "diffuse", "reflectance": 0}}}},
      {{"name": "right", "shape": {{"type": "sphere", "radius": "8 mm"}}, "transform": [{{"translate": [{4}, -0.01, 0]}}],
        "material": {{"type": "diffuse", "reflectance": 0}}}},
      {{"name": "ceiling", "shape": {{"type": "quad", "size": [0.4, 0.4]}},
        "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [0, {5}, 0]}}],
        "material": {{"type": "diffuse", "reflectance": {6}}}}}],
    "lights": [{{"type": "point", "position": [0, {7}, 0], "spectrum": "D65", "scale": {8}}}],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                                                  view, pixels, kN, -x_ball, x_ball, h, kRho, -d, kScale));
  for (const int i : {3, pixels - 1 - 3}) {
    const int j = pixels / 2;
    const double expected = footprint_mean(
        [&](double r) { return layered_ceiling_radiance({{d, kN}, {h, 1.0}}, r); }, view, pixels, i, j);
    const double ratio = film.rgb_at(i, j)[1] / expected;
    std::printf("pixel (%d, %d), its straight segment blocked: %.5f of the closed form\n", i, j, ratio);
    EXPECT_NEAR(ratio, 1.0, 0.005) << "pixel " << i;
  }
}

// The chain's own rays (manifold_chain.h: seeding along the straight segment, retracing at each
// Newton step) are counted with the render's (RenderStats::rays, which --integrator auto's costs
// read): a 20 mm pane between a point above it and a lamp below, two crossings.
TEST(ManifoldNextEvent, TheChainsRaysAreCounted) {
  const SceneDesc desc = parse_scene(R"({
    "camera": {"position": [0, 0.05, 0.3], "look_at": [0, 0, 0], "resolution": [4, 4]},
    "render": {"integrator": "path"},
    "world_medium": "vacuum",
    "media": {"glass": {"ior": 1.5}},
    "objects": [{"name": "pane", "shape": {"type": "box", "size": [2, 0.02, 2]}, "transform": [{"translate": [0, 0.01, 0]}],
                 "inside": "glass"}],
    "background": {"spectrum": "E", "scale": 0}
  })", "pane.json");
  const RenderScene scene = compile(desc);
  const Vec3 x{0.01, 0.1, 0.0}, lamp{-0.02, -0.05, 0.01};
  std::uint64_t rays = 0;
  auto chain = seed_chain(scene, x, nullptr, 0, lamp, rays);
  ASSERT_TRUE(chain);
  EXPECT_EQ(chain->count, 2);
  EXPECT_EQ(rays, 3u) << "to the top face, to the bottom face, on to the lamp";
  const std::uint64_t seeded = rays;
  ASSERT_TRUE(solve_chain(scene, x, nullptr, lamp, *chain, rays));
  EXPECT_GT(rays, seeded) << "Newton's retracing traced no ray, or did not count it";
}

// The plane's solution itself: Snell's law holds at the point found, to 1e-12, for random points
// on both sides and both orders of the indices.
TEST(ManifoldNextEvent, TheRefractionPointObeysSnellsLaw) {
  const Vec3 n = normalize(Vec3{0.2, 1.0, -0.3}), on_plane{0.1, -0.2, 0.05};
  double worst = 0.0;
  for (int k = 0; k < 200; ++k) {
    const double u = 0.618034 * k - std::floor(0.618034 * k), v = 0.414214 * k - std::floor(0.414214 * k);
    auto along_plane = [&](const Vec3& d) { return d - n * dot(d, n); };
    const Vec3 x = on_plane + n * (0.01 + 0.3 * u) + along_plane({0.3 * v - 0.15, 0.0, 0.2 * u - 0.1});
    const Vec3 p = on_plane - n * (0.02 + 0.1 * v) + along_plane({0.1 * u, 0.05, -0.2 * v});
    for (const auto& [ex, ep] : {std::pair{1.0, 1.33}, std::pair{1.5, 1.0}}) {
      const auto y = refraction_point(x, p, on_plane, n, ex, ep);
      ASSERT_TRUE(y);
      EXPECT_NEAR(dot(*y - on_plane, n), 0.0, 1e-12);
      const Vec3 a = normalize(*y - x), b = normalize(p - *y);
      const double sin_a = length(cross(a, n)), sin_b = length(cross(b, n));
      worst = std::max(worst, std::abs(ex * sin_a - ep * sin_b));
      // In the plane of incidence: x, y, p and the normal coplanar.
      EXPECT_NEAR(dot(cross(a, b), n), 0.0, 1e-9);
    }
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_FALSE(refraction_point(Vec3{0, 1, 0}, Vec3{0, 2, 0}, Vec3{}, Vec3{0, 1, 0}, 1.0, 1.33));  // one side
}

// A sphere's solutions: every point found is on the sphere, seen from the outer point, and obeys
// Snell's law in vector form (η_i·u_t = η_o·v_t, u and v the unit directions into and out of it);
// and none is missed: tracing 20 000 rays from the inner point in the plane of the centre and both
// points, refracting them and counting where the outer point changes sides of them finds as many
// paths (but near grazing, below). Random points at every depth (near the centre, near the surface), both orders of the
// indices.
TEST(ManifoldNextEvent, TheSphereRefractionPointsObeySnellsLawAndNoneIsMissed) {
  const Vec3 centre{0.1, -0.2, 0.3};
  constexpr double kR = 0.05;
  Rng rng(7, 0);
  int total = 0, several = 0;
  double worst = 0.0;
  for (int k = 0; k < 300; ++k) {
    auto direction = [&] {
      const double z = 2.0 * rng.next_double() - 1.0, phi = 2.0 * std::numbers::pi * rng.next_double();
      const double r = std::sqrt(1.0 - z * z);
      return Vec3{r * std::cos(phi), r * std::sin(phi), z};
    };
    const Vec3 inner = centre + direction() * (kR * std::cbrt(rng.next_double()) * 0.999);
    const Vec3 outer = centre + direction() * (kR * (1.02 + 3.0 * rng.next_double()));
    const auto [ei, eo] = k % 2 ? std::pair{1.5, 1.0} : std::pair{1.0, 1.33};
    const SphereRefraction found = sphere_refraction_points(inner, outer, centre, kR, ei, eo);
    bool grazing = false;
    for (int i = 0; i < found.count; ++i) {
      const Vec3 y = found.points[static_cast<std::size_t>(i)], n = (y - centre) / kR;
      EXPECT_NEAR(length(y - centre), kR, 1e-12);
      EXPECT_GT(dot(outer - y, n), 0.0);
      grazing = grazing || dot(normalize(outer - y), n) < 0.0175;
      const Vec3 u = normalize(y - inner), v = normalize(outer - y);
      const Vec3 tangential = (u - n * dot(u, n)) * ei - (v - n * dot(v, n)) * eo;
      worst = std::max(worst, length(tangential));
    }
    // The count by tracing: in the plane of the three points, rays from `inner` at angle ψ.
    const Vec3 e1 = normalize(outer - centre);
    const Vec3 across = (inner - centre) - e1 * dot(inner - centre, e1);
    const Vec3 e2 = length(across) > 1e-9 ? normalize(across) : Frame(e1).s;
    int crossings = 0;
    double last = 0.0;
    constexpr int kRays = 20000;
    for (int j = 0; j <= kRays; ++j) {
      const double psi = 2.0 * std::numbers::pi * j / kRays;
      const Vec3 d = e1 * std::cos(psi) + e2 * std::sin(psi);
      const Vec3 o = inner - centre;
      const double b = dot(o, d), t = -b + std::sqrt(b * b - (dot(o, o) - kR * kR));
      const Vec3 y = inner + d * t, n = (y - centre) / kR;
      const double cos_i = dot(d, n), sin_t2 = (ei / eo) * (ei / eo) * (1.0 - cos_i * cos_i);
      double side = 0.0;  // where outer is from the refracted ray, in the plane; 0 where it misses
      if (sin_t2 < 1.0) {
        const Vec3 out = d * (ei / eo) + n * (std::sqrt(1.0 - sin_t2) - (ei / eo) * cos_i);
        if (dot(outer - y, out) > 0.0) side = dot(cross(out, outer - y), cross(e1, e2));
      }
      if (j > 0 && last != 0.0 && side != 0.0 && (last < 0.0) != (side < 0.0)) ++crossings;
      last = side;
    }
    // (Where a path leaves within 1° of grazing, its ray sits at the edge of total internal
    // reflection, where 20 000 rays resolve it no longer: counted by the solve alone.)
    if (!grazing) {
      EXPECT_EQ(found.count, crossings) << "k " << k;
    }
    total += found.count;
    several += found.count > 1;
  }
  std::printf("sphere refraction: %d paths for 300 pairs (%d with more than one), worst |η_i u_t - η_o v_t| %.2e\n",
              total, several, worst);
  EXPECT_LT(worst, 1e-10);
  EXPECT_FALSE(sphere_refraction_points(centre, centre + Vec3{0, 0.5 * kR, 0}, centre, kR, 1.5, 1.0).count);
}

// The sphere's solve against paths built by tracing: a random ray from a random inner point to the
// sphere, refracted out (where it gets out) and on a random distance to the outer point; the solve
// must find that path (a solution within 1e-9 of the radius of its crossing). Outer points close
// to the sphere make close pairs at a caustic's fold, which the scan's sign changes alone miss
// (scan_roots' pair search finds them): without it, 48 intervals missed 7 of the 2368 paths, all
// leaving 62° to 71° from the normal.
TEST(ManifoldNextEvent, TheSphereRefractionPointsFindTheTracedPath) {
  const Vec3 centre{0.1, -0.2, 0.3};
  constexpr double kR = 0.05;
  Rng rng(13, 0);
  int built = 0, found_it = 0, total = 0;
  for (int k = 0; k < 3000; ++k) {
    const auto [ei, eo] = k % 2 ? std::pair{1.5, 1.0} : std::pair{1.0, 1.33};
    auto direction = [&] {
      const double z = 2.0 * rng.next_double() - 1.0, phi = 2.0 * std::numbers::pi * rng.next_double();
      const double r = std::sqrt(1.0 - z * z);
      return Vec3{r * std::cos(phi), r * std::sin(phi), z};
    };
    const Vec3 inner = centre + direction() * (kR * std::cbrt(rng.next_double()) * 0.999);
    const Vec3 d = direction(), o = inner - centre;
    const double b = dot(o, d);
    const Vec3 y = inner + d * (-b + std::sqrt(b * b - (dot(o, o) - kR * kR)));
    const Vec3 n = (y - centre) / kR;
    const double cos_i = dot(d, n), sin_t2 = (ei / eo) * (ei / eo) * (1.0 - cos_i * cos_i);
    if (sin_t2 >= 1.0) continue;
    const Vec3 out = d * (ei / eo) + n * (std::sqrt(1.0 - sin_t2) - (ei / eo) * cos_i);
    const Vec3 outer = y + out * (kR * (0.02 + 3.0 * rng.next_double()));
    ++built;
    const SphereRefraction found = sphere_refraction_points(inner, outer, centre, kR, ei, eo);
    bool has = false;
    for (int i = 0; i < found.count; ++i) has = has || length(found.points[static_cast<std::size_t>(i)] - y) < 1e-9 * kR;
    found_it += has;
    if (!has)
      ADD_FAILURE() << "missed: pair " << k << ", leaving " << std::acos(dot(out, n)) * 180.0 / std::numbers::pi
                    << "° from the normal";
    total += found.count;
  }
  std::printf("sphere refraction: %d of %d traced paths found (%d solutions)\n", found_it, built, total);
  EXPECT_GT(built, 2000);
  EXPECT_EQ(found_it, built);
}

// A cylinder's side (its axis tilted, through a point off the origin): paths built by tracing a
// random ray from a random inner point to the side, refracting it out (where it gets out) and
// going on a random distance to the outer point. The solve must find that path (a solution within
// 1e-9 of the radius of its crossing), and every solution it returns must lie on the side, be
// seen from the outer point and obey Snell's law in vector form (η_i·u_t = η_o·v_t) to 1e-10.
// Both orders of the indices; inner points at every distance from the axis. Where a path and a
// second one lie within one of the scan's 48 intervals (at a caustic's fold) the slope does not
// change sign between its points: the search for the pair (scan_roots) finds them. Without it,
// 48 intervals missed 3 of the 2186 paths (two leaving at 72° and 74° from the normal), 96 missed
// 1 (84°), 144 none; with it, none at 48, 32 or 96 (all: 2259 solutions).
TEST(ManifoldNextEvent, TheCylinderRefractionPointsObeySnellsLawAndFindTheTracedPath) {
  const Vec3 on_axis{0.1, -0.2, 0.3}, axis = normalize(Vec3{1, 2, 3});
  constexpr double kR = 0.05;
  const Frame frame(axis);
  Rng rng(11, 0);
  int built = 0, found_it = 0, total = 0;
  double worst = 0.0;
  for (int k = 0; k < 3000; ++k) {
    const auto [ei, eo] = k % 2 ? std::pair{1.5, 1.0} : std::pair{1.0, 1.33};
    const double r = kR * std::sqrt(rng.next_double()) * 0.999, psi = 2.0 * std::numbers::pi * rng.next_double();
    const Vec3 inner = on_axis + (frame.s * std::cos(psi) + frame.t * std::sin(psi)) * r +
                       axis * (kR * (4.0 * rng.next_double() - 2.0));
    const double z = 2.0 * rng.next_double() - 1.0, phi = 2.0 * std::numbers::pi * rng.next_double();
    const double sz = std::sqrt(1.0 - z * z);
    const Vec3 d = Vec3{sz * std::cos(phi), sz * std::sin(phi), z};
    // To the side: |across(inner + t·d)| = R.
    const Vec3 o = (inner - on_axis) - axis * dot(inner - on_axis, axis), da = d - axis * dot(d, axis);
    const double a = dot(da, da), b = dot(o, da), c = dot(o, o) - kR * kR;
    if (!(a > 1e-12)) continue;
    const Vec3 y = inner + d * ((-b + std::sqrt(b * b - a * c)) / a);
    const Vec3 n = normalize((y - on_axis) - axis * dot(y - on_axis, axis));
    const double cos_i = dot(d, n), sin_t2 = (ei / eo) * (ei / eo) * (1.0 - cos_i * cos_i);
    if (sin_t2 >= 1.0) continue;
    const Vec3 out = d * (ei / eo) + n * (std::sqrt(1.0 - sin_t2) - (ei / eo) * cos_i);
    const Vec3 outer = y + out * (kR * (0.05 + 3.0 * rng.next_double()));
    if (length((outer - on_axis) - axis * dot(outer - on_axis, axis)) <= kR) continue;  // back over the side
    ++built;
    const SphereRefraction found = cylinder_refraction_points(inner, outer, on_axis, axis, kR, ei, eo);
    bool has = false;
    for (int i = 0; i < found.count; ++i) {
      const Vec3 p = found.points[static_cast<std::size_t>(i)];
      const Vec3 across = (p - on_axis) - axis * dot(p - on_axis, axis), np = across / kR;
      EXPECT_NEAR(length(across), kR, 1e-12);
      EXPECT_GT(dot(outer - p, np), 0.0);
      const Vec3 u = normalize(p - inner), v = normalize(outer - p);
      worst = std::max(worst, length((u - np * dot(u, np)) * ei - (v - np * dot(v, np)) * eo));
      has = has || length(p - y) < 1e-9 * kR;
    }
    found_it += has;
    if (!has)
      ADD_FAILURE() << "missed: pair " << k << ", leaving " << std::acos(dot(out, n)) * 180.0 / std::numbers::pi
                    << "° from the normal";
    total += found.count;
  }
  std::printf("cylinder refraction: %d of %d traced paths found (%d solutions), worst |η_i u_t - η_o v_t| %.2e\n",
              found_it, built, total, worst);
  EXPECT_GT(built, 2000);
  EXPECT_EQ(found_it, built);
  EXPECT_LT(worst, 1e-10);
  EXPECT_FALSE(cylinder_refraction_points(on_axis, on_axis + axis, on_axis, axis, kR, 1.5, 1.0).count);  // on the axis
}

// A path through a cylinder's side, in and out (a glass rod between a vertex and a lamp), built by
// tracing: a ray from a random point outside (1.02 to 4 radii from the axis) towards the side,
// refracted in, across, refracted out (where it gets out), and on to a point 0.05 to 3 radii along
// it, outside. Indices inside and outside by k: glass, water, and air bubbles in water.
struct TracedRodPath {
  Vec3 from, to, y1, y2;
  double eta_inside, eta_outside;
  bool grazing;  // entering or leaving within 3° of grazing
};
std::optional<TracedRodPath> traced_rod_path(int k, Rng& rng, const Vec3& on_axis, const Vec3& axis, double radius_m) {
  const Frame frame(axis);
  const double kR = radius_m;
  auto across = [&](const Vec3& p) { return (p - on_axis) - axis * dot(p - on_axis, axis); };
  const auto [ei, eo] = k % 3 == 0 ? std::pair{1.5, 1.0} : k % 3 == 1 ? std::pair{1.33, 1.0} : std::pair{1.0, 1.33};
  const double r = kR * (1.02 + 3.0 * rng.next_double()), psi = 2.0 * std::numbers::pi * rng.next_double();
  const Vec3 from = on_axis + (frame.s * std::cos(psi) + frame.t * std::sin(psi)) * r +
                    axis * (kR * (4.0 * rng.next_double() - 2.0));
  // Towards a random point of the side within two radii of `from`'s height (most such rays enter).
  const double phi = 2.0 * std::numbers::pi * rng.next_double();
  const Vec3 aim = on_axis + (frame.s * std::cos(phi) + frame.t * std::sin(phi)) * kR +
                   axis * (dot(from - on_axis, axis) + kR * (4.0 * rng.next_double() - 2.0));
  const Vec3 d = normalize(aim - from);
  // Into the side: the nearer root of |across(from + t·d)| = R.
  const Vec3 o = across(from), da = d - axis * dot(d, axis);
  const double qa = dot(da, da), qb = dot(o, da), qc = dot(o, o) - kR * kR;
  if (!(qa > 1e-12) || qb * qb - qa * qc <= 0.0) return std::nullopt;
  const double t_in = (-qb - std::sqrt(qb * qb - qa * qc)) / qa;
  if (!(t_in > 0.0)) return std::nullopt;
  auto refract = [](const Vec3& u, const Vec3& n, double eta) -> std::optional<Vec3> {  // n against u
    const double c = -dot(u, n), s2 = eta * eta * (1.0 - c * c);
    if (s2 >= 1.0) return std::nullopt;
    return u * eta + n * (eta * c - std::sqrt(1.0 - s2));
  };
  const Vec3 y1 = from + d * t_in, n1 = across(y1) / kR;
  const auto t = refract(d, n1, eo / ei);
  if (!t) return std::nullopt;
  // Out: the far root along t from y1 (on the side: across(y1) has length R).
  const Vec3 ta = *t - axis * dot(*t, axis);
  if (!(dot(ta, ta) > 1e-12)) return std::nullopt;
  const Vec3 y2 = y1 + *t * (-2.0 * dot(across(y1), ta) / dot(ta, ta)), n2 = across(y2) / kR;
  const auto out = refract(*t, -n2, ei / eo);
  if (!out) return std::nullopt;  // totally reflected inside: a walk's path
  const Vec3 to = y2 + *out * (kR * (0.05 + 3.0 * rng.next_double()));
  if (length(across(to)) <= kR) return std::nullopt;
  // A path entering or leaving within 3° of grazing sits on the edge of the arc the solve scans,
  // as in the sphere's test.
  return TracedRodPath{from, to, y1, y2, ei, eo, -dot(d, n1) < 0.05 || dot(*out, n2) < 0.05};
}

// The solve finds each traced path (traced_rod_path), and every path it finds obeys Snell's law at
// both crossings (the whole tangential vector: along the axis and around it, which checks
// Bravais' reduction as well as the circle's solve) and reaches its far end. An axis invariant
// taken from the wrong index, a rise per unit across of the wrong segment, or a passage followed
// to the wrong neighbour loses paths here.
TEST(ManifoldNextEvent, TheCylinderPassagesObeySnellsLawTwiceAndFindTheTracedPath) {
  const Vec3 on_axis{0.1, -0.2, 0.3}, axis = normalize(Vec3{-2, 1, 3});
  constexpr double kR = 0.04;
  Rng rng(12, 0);
  auto across = [&](const Vec3& p) { return (p - on_axis) - axis * dot(p - on_axis, axis); };
  int built = 0, found_it = 0, total = 0, grazing = 0;
  double worst = 0.0;
  for (int k = 0; k < 1500; ++k) {
    const std::optional<TracedRodPath> traced = traced_rod_path(k, rng, on_axis, axis, kR);
    if (!traced) continue;
    const auto& [from, to, y1, y2, ei, eo, near_grazing] = *traced;
    ++built;
    const SpherePassages found = cylinder_passage_points(from, to, on_axis, axis, kR, ei, eo);
    bool has = false;
    for (int i = 0; i < found.count; ++i) {
      const Vec3 p1 = found.entry[static_cast<std::size_t>(i)], p2 = found.exit[static_cast<std::size_t>(i)];
      EXPECT_NEAR(length(across(p1)), kR, 1e-12);
      EXPECT_NEAR(length(across(p2)), kR, 1e-12);
      const Vec3 m1 = across(p1) / kR, m2 = across(p2) / kR;
      const Vec3 u = normalize(p1 - from), v = normalize(p2 - p1), w = normalize(to - p2);
      EXPECT_LT(dot(u, m1), 0.0);
      EXPECT_GT(dot(w, m2), 0.0);
      worst = std::max({worst, length((u - m1 * dot(u, m1)) * eo - (v - m1 * dot(v, m1)) * ei),
                        length((v - m2 * dot(v, m2)) * ei - (w - m2 * dot(w, m2)) * eo)});
      has = has || (length(p1 - y1) < 1e-9 * kR && length(p2 - y2) < 1e-9 * kR);
    }
    if (near_grazing) {
      ++grazing;
      continue;
    }
    found_it += has;
    if (!has) ADD_FAILURE() << "missed: pair " << k;
    total += found.count;
  }
  std::printf("cylinder passages: %d of %d traced paths found (%d within 3° of grazing, not counted; %d solutions), "
              "worst |η u_t - η' v_t| %.2e\n",
              found_it, built - grazing, grazing, total, worst);
  EXPECT_GT(built - grazing, 1100);
  EXPECT_EQ(found_it, built - grazing);
  EXPECT_LT(worst, 1e-10);
}

// A point lamp inside a ball of absorbing glass (on its axis, half the radius below its centre)
// lights a ceiling only through the ball's surface. The closed form as for the water, by the ray
// from the lamp at α from the vertical: it leaves the ball at y(α) after the chord t(α), refracts
// and meets the ceiling at radius R(α) (increasing over the view: one path to each point), so
//   E(R) = T(α)·exp(−σ_a·t(α))·I·sin α / (R·dR/dα),
// dR/dα by central differences. Direct light only (max_depth 1): the light reflected inside the
// ball before it leaves is the light tracer's to find (no strategy of the path tracer meets a point
// lamp after a reflection). Every pixel within 0.5 % and the mean within 0.1 %: the same
// failures as above fail, and a missing absorption along the chord (exp(−σ_a·t) is 0.41 on the
// axis), a ray tube of the straight line (the lamp seen without the ball's lens) or a path lost in
// the solve.
constexpr double kBallR_m = 0.03, kLampBelow_m = 0.015, kBallN = 1.5, kSigmaA = 20.0;

double ball_ceiling_radiance(double r) {
  struct Exit {
    double reach = 0.0, chord = 0.0, transmittance = 0.0;
  };
  auto trace = [](double a) {
    const double b = -kLampBelow_m * std::cos(a), c = kLampBelow_m * kLampBelow_m - kBallR_m * kBallR_m;
    const double t = -b + std::sqrt(b * b - c);
    const double yr = t * std::sin(a), yy = -kLampBelow_m + t * std::cos(a), nr = yr / kBallR_m, ny = yy / kBallR_m;
    const double cos_i = std::sin(a) * nr + std::cos(a) * ny, sin_t2 = kBallN * kBallN * (1.0 - cos_i * cos_i);
    const double cos_t = std::sqrt(1.0 - sin_t2);
    const double or_ = kBallN * std::sin(a) + (cos_t - kBallN * cos_i) * nr,
                 oy = kBallN * std::cos(a) + (cos_t - kBallN * cos_i) * ny;
    return Exit{yr + (kCeiling_m - yy) * or_ / oy, t, 1.0 - fresnel_dielectric(cos_i, cos_t, kBallN, 1.0)};
  };
  double lo = 1e-9, hi = 1.8;
  for (int i = 0; i < 200; ++i) ((trace(0.5 * (lo + hi)).reach < r) ? lo : hi) = 0.5 * (lo + hi);
  const double a = 0.5 * (lo + hi), h = 1e-6;
  const double dr = (trace(a + h).reach - trace(a - h).reach) / (2.0 * h);
  const Exit e = trace(a);
  return kRho * e.transmittance * std::exp(-kSigmaA * e.chord) * kScale * std::sin(a) / (r * dr) / std::numbers::pi;
}

// A point lamp at height lamp_y inside `glass` (an object of the absorbing glass, index n) under
// the ceiling, seen from below it by an orthographic camera at camera_y, direct light only.
std::string lamp_in_glass_scene(double camera_y, double n, const std::string& glass, double lamp_y) {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, {}, 0], "look_at": [0, 1, 0], "up": [0, 0, -1],
               "width": {}, "resolution": [{}, {}]}},
    "render": {{"integrator": "path", "spectral": "full", "spp": 64, "max_depth": 1, "seed": 5}},
    "world_medium": "vacuum",
    "media": {{"glass": {{"ior": {}, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [380, 780],
                                                    "value": [{}, {}]}}}}}},
    "objects": [
      {},
      {{"name": "ceiling", "shape": {{"type": "quad", "size": [0.4, 0.4]}},
        "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [0, {}, 0]}}],
        "material": {{"type": "diffuse", "reflectance": {}}}}}
    ],
    "lights": [{{"type": "point", "position": [0, {}, 0], "spectrum": "D65", "scale": {}}}],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                     camera_y, kView_m, kPixels, kPixels, n, kSigmaA, kSigmaA, glass, kCeiling_m, kRho, lamp_y, kScale);
}

std::string lamp_in_ball_scene(const char* tessellation) {
  return lamp_in_glass_scene(
      0.035, kBallN,
      fmt::format(R"({{"name": "ball", "shape": {{"type": "sphere", "radius": {}{}}}, "inside": "glass"}})", kBallR_m,
                  tessellation),
      -kLampBelow_m);
}

TEST(ManifoldNextEvent, PointLampInsideAGlassBallLightsTheCeilingAsTheClosedFormSays) {
  const Film film = test::render_text(lamp_in_ball_scene(""));
  const auto [mean, worst] = ceiling_ratio(film, ball_ceiling_radiance);
  std::printf("point lamp in a glass ball: ceiling / closed form, mean %.5f, worst pixel %.2e\n", mean, worst);
  EXPECT_LT(worst, 0.005);
  EXPECT_NEAR(mean, 1.0, 0.001);
}

// The same ball tessellated, its vertices carrying the sphere's normals: the chain's Newton solve
// (manifold_chain.h) refracts by the interpolated shading normals, as the walk does, where the
// facets' own normals would break the ceiling into a mosaic of the facets' images. Against the
// exact sphere's closed form: the facets stand in for the sphere only to their sagitta (0.05 % of
// the radius at 192 segments) and their normals interpolate the sphere's to about 1e-4 rad, so the
// ceiling is within 1 % a pixel and 0.2 % on the mean (measured: 0.09 % and 0.007 %); refracted
// by the facets' normals instead, the mean is 0.29 of it and pixels are off by up to 93 %.
TEST(ManifoldNextEvent, PointLampInsideASmoothShadedBallLightsTheCeilingAsTheSphere) {
  const Film film = test::render_text(lamp_in_ball_scene(R"(, "tessellate": true, "segments": 192)"));
  const auto [mean, worst] = ceiling_ratio(film, ball_ceiling_radiance);
  std::printf("point lamp in a smooth-shaded tessellated glass ball: ceiling / the sphere's closed form, mean %.5f, "
              "worst pixel %.2e\n", mean, worst);
  EXPECT_LT(worst, 0.01);
  EXPECT_NEAR(mean, 1.0, 0.002);
}

// A point lamp on the axis of a long rod of absorbing glass (an exact cylinder lying along x, 40 mm
// across) lights a ceiling H above the axis only through the rod's side. Every ray from a lamp on
// the axis stays in its plane through the axis (the side's normal is radial), where the side is a
// straight line: at θ from the radial direction the ray leaves R·tan θ along the axis, refracted
// to θ′ (sin θ′ = n·sin θ), and meets the ceiling's line in that plane, ρ = √(H² + z²) from the
// axis, at x(θ) = R·tan θ + (ρ − R)·tan θ′ (increasing: one path to each point). The solid angle
// cos θ dθ dψ lands on dx·dz = x′(θ)·(H/cos²ψ) dθ dψ (z = H·tan ψ), so
//   E(x, z) = T(θ)·exp(−σ_a·R/cos θ)·I·cos θ·cos²ψ / (x′(θ)·H),
// x′ by central differences.
constexpr double kRodR_m = 0.02, kRodN = 1.5;
double rod_ceiling_radiance(double x, double z) {
  const double rho = std::hypot(kCeiling_m, z), cos_psi = kCeiling_m / rho;
  auto reach = [&](double a) {
    const double sin_b = kRodN * std::sin(a);
    return kRodR_m * std::tan(a) + (rho - kRodR_m) * sin_b / std::sqrt(1.0 - sin_b * sin_b);
  };
  double lo = -std::asin(1.0 / kRodN) * (1.0 - 1e-9), hi = -lo;
  for (int i = 0; i < 200; ++i) ((reach(0.5 * (lo + hi)) < x) ? lo : hi) = 0.5 * (lo + hi);
  const double a = 0.5 * (lo + hi), h = 1e-6;
  const double dx = (reach(a + h) - reach(a - h)) / (2.0 * h);
  const double cos_a = std::cos(a), sin_b = kRodN * std::sin(a), cos_b = std::sqrt(1.0 - sin_b * sin_b);
  const double t = 1.0 - fresnel_dielectric(cos_a, cos_b, kRodN, 1.0);
  const double e = t * std::exp(-kSigmaA * kRodR_m / cos_a) * kScale * cos_a * cos_psi * cos_psi / (dx * kCeiling_m);
  return kRho * e / std::numbers::pi;
}

// Every pixel within 0.5 % of the closed form over its footprint and the mean within 0.1 %, as for
// the ball. Before, a shadow ray stopped by a cylinder's side had no solve and the ceiling was
// black; a ray tube of the straight line, a missing Fresnel factor or the absorption left out
// (exp(−σ_a·R) = 0.67 under the lamp) fails.
TEST(ManifoldNextEvent, PointLampInsideAGlassRodLightsTheCeilingAsTheClosedFormSays) {
  const Film film = test::render_text(lamp_in_glass_scene(
      0.025, kRodN,
      fmt::format(R"({{"name": "rod", "shape": {{"type": "cylinder", "radius": {}, "height": 0.4}},
                       "transform": [{{"translate": [0, -0.2, 0]}}, {{"rotate_deg": [90, [0, 0, 1]]}}],
                       "inside": "glass"}})",
                  kRodR_m),
      0.0));
  const auto [mean, worst] = ceiling_ratio(film, rod_ceiling_radiance);
  std::printf("point lamp in a glass rod: ceiling / closed form, mean %.5f, worst pixel %.2e\n", mean, worst);
  EXPECT_LT(worst, 0.005);
  EXPECT_NEAR(mean, 1.0, 0.001);
}

// The ray tube at x of the path through f whose crossings are ys, by full solves at the two
// neighbours 1e-6 of the path away across wi (the whole arc scanned, the path whose last crossing
// is nearest this one's taken): what tube()'s windowed neighbour solves should give.
double tube_by_full_solves(const manifold_detail::Interface& f, const Vec3& x, const Vec3& wi,
                           const std::array<Vec3, 2>& ys, int crossings, const Vec3& q, double path_m, double eta_front,
                           double eta_behind) {
  using namespace manifold_detail;
  const double step = 1e-6 * path_m;
  const auto last = static_cast<std::size_t>(crossings - 1);
  auto o_at = [&](const Vec3& by) {
    const Paths m = solve(f, x + by * step, q, eta_front, eta_behind);
    EXPECT_GE(m.count, 1);
    Vec3 best = m.crossing[0][last];
    for (int k = 1; k < m.count; ++k)
      if (length(m.crossing[static_cast<std::size_t>(k)][last] - ys[last]) < length(best - ys[last]))
        best = m.crossing[static_cast<std::size_t>(k)][last];
    return normalize(best - q);
  };
  const Frame frame(wi);
  const Vec3 o0 = normalize(ys[last] - q), o1 = o_at(frame.s), o2 = o_at(frame.t);
  return length(cross(o1 - o0, o2 - o0)) / (step * step);
}

// The ray tube of a path from a vertex inside a cylinder or a sphere (40 mm across) to a point
// lamp 3.2 m away, 80 radii: tube()'s neighbour solves against the same finite differences by full
// solves (the whole arc scanned, the path nearest the first one's taken), within 1e-4. Before,
// the neighbours looked within a fixed 1e-4 rad of the first crossing, which a step of 1e-6 of the
// path moves farther than that: no path, a tube of 0 and the lamp's light lost.
TEST(ManifoldNextEvent, TheRayTubeOfALongPathFromInsideACylinderOrASphere) {
  using namespace manifold_detail;
  constexpr double kR = 0.02, kIn = 1.33, kOut = 1.0;
  const Vec3 x{0.003, 0.002, -0.004}, q{3.2, 0.4, 0.3};
  for (const Interface::Shape shape : {Interface::Shape::cylinder, Interface::Shape::sphere}) {
    const Interface f{0, shape, Vec3{}, Vec3{0, 0, 1}, kR};
    const Paths p = solve(f, x, q, kOut, kIn);
    ASSERT_EQ(p.count, 1);
    const std::array<Vec3, 2>& ys = p.crossing[0];
    const double path_m = length(ys[0] - x) + length(q - ys[0]);
    const Vec3 wi = normalize(ys[0] - x);
    const double t = tube(f, x, wi, ys, 1, q, path_m, kOut, kIn);
    const double reference = tube_by_full_solves(f, x, wi, ys, 1, q, path_m, kOut, kIn);
    std::printf("tube from inside a %s 80 radii from the lamp: %.6e, by full solves %.6e\n",
                shape == Interface::Shape::cylinder ? "cylinder" : "sphere", t, reference);
    EXPECT_GT(reference, 0.0);
    EXPECT_NEAR(t / reference, 1.0, 1e-4);
  }
}

// The same through a glass rod and a glass ball, in and out (a vertex 15 mm from the surface, the
// lamp 3.2 m away on the far side): tube()'s neighbour solves, which look only within a window of
// the path's own entry angle and axis invariant, against full solves, within 1e-4. A window in β
// too narrow for the neighbour's step (it moves β by about the step over the way to the entry
// point) loses the path and reads 0; one around the wrong β reads another path's tube.
TEST(ManifoldNextEvent, TheRayTubeOfALongPathThroughARodOrABall) {
  using namespace manifold_detail;
  constexpr double kR = 0.02, kIn = 1.5, kOut = 1.0;
  const Vec3 x{0.031, -0.012, 0.004}, q{-3.1, 0.5, 0.6};
  for (const Interface::Shape shape : {Interface::Shape::cylinder, Interface::Shape::sphere}) {
    const Interface f{0, shape, Vec3{}, Vec3{0, 0, 1}, kR};
    const Paths p = solve(f, x, q, kOut, kIn);
    ASSERT_GE(p.count, 1);
    ASSERT_EQ(p.crossings, 2);
    for (int k = 0; k < p.count; ++k) {
      const std::array<Vec3, 2>& ys = p.crossing[static_cast<std::size_t>(k)];
      const double path_m = length(ys[0] - x) + length(ys[1] - ys[0]) + length(q - ys[1]);
      const Vec3 wi = normalize(ys[0] - x);
      const double t = tube(f, x, wi, ys, 2, q, path_m, kOut, kIn);
      const double reference = tube_by_full_solves(f, x, wi, ys, 2, q, path_m, kOut, kIn);
      std::printf("tube through a %s (path %d of %d), 160 radii from the lamp: %.6e, by full solves %.6e\n",
                  shape == Interface::Shape::cylinder ? "rod" : "ball", k + 1, p.count, t, reference);
      EXPECT_GT(reference, 0.0);
      EXPECT_NEAR(t / reference, 1.0, 1e-4);
    }
  }
}

// The ray tubes of traced paths through a rod (traced_rod_path: the vertex 0.02 to 3 radii from
// the side, the lamp 0.05 to 3 radii beyond it, in glass, water and bubbles), by tube()'s
// neighbour solves (Newton's method from the straight line to the path's entry point, the
// window's grid where it finds nothing within the window) against the same finite differences by
// full solves. A neighbour that Newton's method took to another path reads that path's tube:
// started 0.6 rad off and its root taken wherever it lay, 143 of the 472 failed.
TEST(ManifoldNextEvent, TheRayTubesOfTracedPathsThroughARodAreTheFullSolves) {
  using namespace manifold_detail;
  const Vec3 on_axis{0.1, -0.2, 0.3}, axis = normalize(Vec3{-2, 1, 3});
  constexpr double kR = 0.04;
  const Interface f{0, Interface::Shape::cylinder, on_axis, axis, kR};
  Rng rng(21, 0);
  int compared = 0, off = 0;
  double worst = 0.0;
  std::vector<double> errors;
  for (int k = 0; k < 600; ++k) {
    const std::optional<TracedRodPath> traced = traced_rod_path(k, rng, on_axis, axis, kR);
    if (!traced || traced->grazing) continue;
    const Paths p = solve(f, traced->from, traced->to, traced->eta_outside, traced->eta_inside);
    for (int i = 0; i < p.count; ++i) {
      const std::array<Vec3, 2>& ys = p.crossing[static_cast<std::size_t>(i)];
      if (p.crossings != 2 || length(ys[0] - traced->y1) > 1e-9 * kR) continue;  // the traced path
      const double path_m = length(ys[0] - traced->from) + length(ys[1] - ys[0]) + length(traced->to - ys[1]);
      const Vec3 wi = normalize(ys[0] - traced->from);
      const double t = tube(f, traced->from, wi, ys, 2, traced->to, path_m, traced->eta_outside, traced->eta_inside);
      const double reference =
          tube_by_full_solves(f, traced->from, wi, ys, 2, traced->to, path_m, traced->eta_outside, traced->eta_inside);
      ++compared;
      const double error = std::abs(t / reference - 1.0);
      errors.push_back(error);
      worst = std::max(worst, error);
      if (!(error < 1e-4)) {
        ++off;
        ADD_FAILURE() << "path " << k << ": tube " << t << ", by full solves " << reference;
      }
    }
  }
  std::sort(errors.begin(), errors.end());
  std::printf("rod tubes: %d compared, %d off by 1e-4 or more, median %.1e, worst %.1e\n", compared, off,
              errors.empty() ? 0.0 : errors[errors.size() / 2], worst);
  EXPECT_GT(compared, 400);
}

// A point lamp in air lights a floor under flat water (a box's face) along a refracted path that
// passes 5.8 mm from a small glass ball (5 mm, an exact sphere: a caster) standing on the
// straight line between them. The straight shadow ray meets the water's face first, and the face's
// own solve reaches the lamp past the ball: the floor under it as bright as without the ball
// (within 1 %: the camera's rays refract at the water with probability 1 − F, the same draws in
// both). A shadow ray skipped because the straight segment crosses the ball (`caster_between`,
// once applied to point lamps too) left it black.
TEST(ManifoldNextEvent, ABallBesideTheRefractedPathCastsNoShadowOfTheStraightOne) {
  auto floor = [](bool ball) {
    const std::string json = fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                 "width": 0.004, "resolution": [8, 8]}},
      "render": {{"integrator": "path", "spectral": "full", "spp": 16, "max_depth": 4, "seed": 3}},
      "world_medium": "vacuum",
      "media": {{"water": {{"ior": 1.33}}, "glass": {{"ior": 1.5}}}},
      "objects": [
        {{"name": "water", "shape": {{"type": "box", "size": [2, 0.2, 2]}}, "transform": [{{"translate": [0, -0.1, 0]}}],
          "inside": "water"}},
        {{"name": "floor", "shape": {{"type": "quad", "size": [0.5, 0.5]}},
          "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}, {{"translate": [0, -0.1, 0]}}],
          "material": {{"type": "diffuse", "reflectance": 0.8}}}}{}
      ],
      "lights": [{{"type": "point", "position": [0.4, 0.3, 0], "spectrum": "D65", "scale": 0.01}}],
      "background": {{"spectrum": "E", "scale": 0}}
    }})",
                                         ball ? R"(,
        {"name": "ball", "shape": {"type": "sphere", "radius": 0.005}, "transform": [{"translate": [0.25, 0.15, 0]}],
         "inside": "glass"})"
                                              : "");
    const Film film = test::render_text(json);
    double sum = 0.0;
    for (int j = 0; j < film.height; ++j)
      for (int i = 0; i < film.width; ++i) sum += film.rgb_at(i, j)[1];
    return sum / (film.width * film.height);
  };
  const double with = floor(true), without = floor(false);
  std::printf("floor under water beside a ball on the straight line: %.6f, without the ball %.6f\n", with, without);
  EXPECT_GT(without, 0.0);
  EXPECT_NEAR(with / without, 1.0, 0.01);
}

// From scattering events in a liquid, through the glass of a smooth-shaded tumbler (a vessel: its
// walls meshes with the surface of revolution's normals), to a point and a spot lamp: the lit
// tumbler of test_bdpt.cpp with the glass at n = 1.0001 and the liquid at 1.0002 in vacuum, so the
// chain of two or three crossings is solved (walls, the liquid's surface and the wall above it)
// yet bends the paths by almost nothing, against the same tumbler index-matched (n = 1 throughout),
// where the shadow rays go straight through and no solve is needed. The liquid's mean over the
// pixels, the path tracer at 1024 samples, two seeds each: measured 0.6 % apart (0.08476 against
// 0.08531), where two seeds' spread made the standard errors look like 0.15 % and 0.02 %; at 4096
// samples and four seeds 0.2 % apart (0.08504 ± 0.00005 against 0.08486 ± 0.00007). Asserted
// within 1.5 %. Before shadow rays were
// aimed at their target from their offset origin (transmission), a segment through the 2 mm wall
// was blocked by the wall's other face: 17 % dark under the spot, 37 % under the point lamp.
TEST(ManifoldNextEvent, LitTumblerThroughItsWallsMatchesTheIndexMatchedTumbler) {
  auto liquid = [](double glass_n, double liquid_n) {
    nlohmann::json scene = nlohmann::json::parse(test::lit_tumbler("path"));
    scene["world_medium"] = "vacuum";
    scene["media"]["glass"]["ior"] = glass_n;
    scene["media"]["haze"]["ior"] = liquid_n;
    scene["render"]["spectral"] = "full";
    scene["render"]["spp"] = 1024;
    const std::string json = scene.dump();
    SceneDesc desc = parse_scene(json, "tumbler.json");
    std::vector<double> means;
    for (const Film& f : test::render_seeds(desc, 2, 1)) means.push_back(test::channel_estimate(f, 1, 5, 6, 11, 14).mean);
    return test::mean_estimate(means);
  };
  const test::Estimate solved = liquid(1.0001, 1.0002), straight = liquid(1.0, 1.0);
  std::printf("the lit tumbler's liquid: solved through the glass %.5f ± %.5f, index-matched %.5f ± %.5f\n",
              solved.mean, solved.standard_error, straight.mean, straight.standard_error);
  EXPECT_NEAR(solved.mean / straight.mean, 1.0, 0.015);
}

// A scattering liquid in a box, index-matched to the water all around it (the camera's medium too),
// lit by a point lamp inside a box of air 170 mm away: the shadow ray leaves the liquid
// unrefracted, crosses the water and meets the air box's face, where the flat solve takes it on.
// The segment's first stretch is the liquid's, not the water's that the face touches: before,
// the liquid's extinction on it was left out and the liquid came out 1.72× the light tracer's
// (which connects its scattering events straight to the camera here). Asserted: the path tracer's
// mean over the liquid within 4 standard errors of the light tracer's (two seeds each; the light
// tracer's error about 1 %). The path tracer leaves out light reflected inside the air box before
// it leaves (its faces reflect 2 % at normal incidence): measured 0.7 % below.
TEST(ManifoldNextEvent, ALiquidBehindAMatchedBoundaryMatchesTheLightTracer) {
  const SceneDesc desc = parse_scene(R"({
    "camera": {"position": [0, 0.06, 0.26], "look_at": [0, 0.045, 0], "fov_deg": 22, "resolution": [16, 16]},
    "render": {"integrator": "path", "spectral": "full", "max_depth": 64},
    "world_medium": "water",
    "media": {"water": {"ior": 1.33}, "gas": {"ior": 1.0},
              "haze": {"ior": 1.33, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                   "value": [30, 15], "phase": {"type": "henyey_greenstein", "g": 0.3}}}},
    "objects": [
      {"name": "liquid", "shape": {"type": "box", "size": [0.06, 0.07, 0.06]}, "transform": [{"translate": [0, 0.04, 0]}],
       "inside": "haze"},
      {"name": "bubble", "shape": {"type": "box", "size": [0.04, 0.04, 0.04]}, "transform": [{"translate": [0.2, 0.05, 0]}],
       "inside": "gas"}
    ],
    "lights": [{"type": "point", "position": [0.2, 0.05, 0], "spectrum": "D65", "scale": 0.05}]
  })", "bubble.json");
  auto liquid = [&](IntegratorType integrator, int spp) {
    SceneDesc d = desc;
    d.render.integrator = integrator;
    d.render.spp = spp;
    std::vector<double> means;
    for (const Film& f : test::render_seeds(d, 2, 1)) means.push_back(test::channel_estimate(f, 1, 5, 6, 11, 14).mean);
    return test::mean_estimate(means);
  };
  const test::Estimate path = liquid(IntegratorType::path, 256), light = liquid(IntegratorType::light, 4096);
  std::printf("a liquid behind a matched boundary, a lamp in air: path %.5f ± %.5f, light tracer %.5f ± %.5f\n",
              path.mean, path.standard_error, light.mean, light.standard_error);
  EXPECT_LT(std::abs(path.mean - light.mean), 4.0 * std::hypot(path.standard_error, light.standard_error));
  EXPECT_LT(light.standard_error, 0.02 * light.mean) << "too noisy to compare";
}

// A globe of absorbing glass with a point lamp inside it (off its centre) in a ball of coloured fog
// (index 1, nested by priority): the fog's scattering events reach the lamp only through the globe,
// which the path tracer's medium vertices now solve for. The light tracer reaches the same light
// from the lamp's side (its paths leave the globe, scatter and connect to the camera). Compared
// where the camera does not see the globe (four bands around it: the light tracer cannot connect
// through it), the means agree within 4 standard errors (each's from the spread of 4 seeds'
// means, about 1 %); the light reflected inside the globe, which only the light tracer finds, is
// F·T² ≈ 0.4 % of it (T = 0.3 across the radius). Without the solve at medium vertices the fog
// is black to the path tracer; where tracking's estimate of the straight shadow ray was 0 and the
// solve was skipped, it was 12 % dark; a ray tube of the straight line (without the glass's lens)
// or no absorption along the chord fail too. The Fresnel factor's 4 % is at the tolerance's edge
// (the ball's closed form above holds it to 0.1 %).
TEST(ManifoldNextEvent, FogAroundAGlobeWithALampInsideMatchesTheLightTracer) {
  auto scene = [](const char* integrator, int spp) {
    return parse_scene(fmt::format(R"({{
    "camera": {{"position": [0, 0, 0.3], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [24, 24]}},
    "render": {{"integrator": "{}", "spectral": "full", "spp": {}, "seed": 1}},
    "world_medium": "vacuum",
    "media": {{"glass": {{"ior": 1.5, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [380, 780],
                                                     "value": [40, 40]}}}},
              "fog": {{"ior": 1.0, "scattering": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                       "value": [8, 2], "phase": {{"type": "henyey_greenstein", "g": 0.3}}}}}}}},
    "objects": [
      {{"name": "fog", "shape": {{"type": "sphere", "radius": 0.1}}, "inside": "fog", "priority": 1}},
      {{"name": "globe", "shape": {{"type": "sphere", "radius": 0.03}}, "inside": "glass", "priority": 2}}
    ],
    "lights": [{{"type": "point", "position": [0.012, 0.008, 0.004], "spectrum": "D65", "scale": 0.01}}],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                                   integrator, spp),
                       "globe.json");
  };
  const std::vector<Film> path = test::render_seeds(scene("path", 128), 4, 1);
  const std::vector<Film> light = test::render_seeds(scene("light", 256), 4, 1);
  struct Band {
    int x0, y0, x1, y1;
  };
  for (const Band& r : {Band{0, 0, 24, 6}, Band{0, 18, 24, 24}, Band{0, 6, 6, 18}, Band{18, 6, 24, 18}})
    for (int c = 0; c < 3; ++c) {
      const test::Estimate a = test::seeds_estimate(path, c, r.x0, r.y0, r.x1, r.y1);
      const test::Estimate b = test::seeds_estimate(light, c, r.x0, r.y0, r.x1, r.y1);
      const double se = std::hypot(a.standard_error, b.standard_error);
      std::printf("fog around a lit globe [%d, %d) x [%d, %d) ch %d: path %.5f ± %.5f, light %.5f ± %.5f\n", r.x0,
                  r.x1, r.y0, r.y1, c, a.mean, a.standard_error, b.mean, b.standard_error);
      EXPECT_LT(se, 0.025 * b.mean) << "too noisy for the test to catch a 10 % error";
      EXPECT_NEAR(a.mean, b.mean, 4.0 * se) << "ch " << c;
    }
}

// Two crossings: every entry and exit point found obeys Snell's law in vector form at both, and
// none is missed: tracing 20 000 rays from `from` in the plane of the centre and both points
// through the sphere and counting where `to` changes sides of the rays that leave finds as many
// paths (but where a path meets the sphere within 3° of grazing, where the rays resolve it no
// longer). Random points at distances from 1.02 to 4
// radii, both orders of the indices.
TEST(ManifoldNextEvent, TheSpherePassagesObeySnellsLawTwiceAndNoneIsMissed) {
  const Vec3 centre{-0.1, 0.2, 0.05};
  constexpr double kR = 0.04;
  Rng rng(11, 0);
  int total = 0, checked = 0;
  double worst = 0.0;
  auto snell = [&](const Vec3& a, const Vec3& y, const Vec3& b, double ea, double eb) {
    const Vec3 n = (y - centre) / kR, u = normalize(y - a), v = normalize(b - y);
    return length((u - n * dot(u, n)) * ea - (v - n * dot(v, n)) * eb);
  };
  for (int k = 0; k < 300; ++k) {
    auto direction = [&] {
      const double z = 2.0 * rng.next_double() - 1.0, phi = 2.0 * std::numbers::pi * rng.next_double();
      const double r = std::sqrt(1.0 - z * z);
      return Vec3{r * std::cos(phi), r * std::sin(phi), z};
    };
    const Vec3 from = centre + direction() * (kR * (1.02 + 3.0 * rng.next_double()));
    const Vec3 to = centre + direction() * (kR * (1.02 + 3.0 * rng.next_double()));
    const double ei = k % 2 ? 1.5 : 1.33, eo = 1.0;
    const SpherePassages found = sphere_passage_points(from, to, centre, kR, ei, eo);
    bool grazing = false;
    for (int i = 0; i < found.count; ++i) {
      const Vec3 y1 = found.entry[static_cast<std::size_t>(i)], y2 = found.exit[static_cast<std::size_t>(i)];
      EXPECT_NEAR(length(y1 - centre), kR, 1e-12);
      EXPECT_NEAR(length(y2 - centre), kR, 1e-12);
      worst = std::max({worst, snell(from, y1, y2, eo, ei), snell(y1, y2, to, ei, eo)});
      grazing = grazing || dot(normalize(to - y2), (y2 - centre) / kR) < 0.05 ||
                dot(normalize(from - y1), (y1 - centre) / kR) < 0.05;
    }
    const Vec3 e1 = normalize(from - centre);
    const Vec3 across = (to - centre) - e1 * dot(to - centre, e1);
    const Vec3 e2 = normalize(across), up = cross(e1, e2);
    int crossings = 0;
    double last = 0.0;
    constexpr int kRays = 20000;
    for (int j = 0; j <= kRays; ++j) {
      const double psi = 2.0 * std::numbers::pi * j / kRays;
      const Vec3 d = e1 * -std::cos(psi) + e2 * std::sin(psi);  // about the direction towards the centre
      double side = 0.0;
      const Vec3 o = from - centre;
      const double b = dot(o, d), disc = b * b - (dot(o, o) - kR * kR);
      if (disc > 0.0 && -b - std::sqrt(disc) > 0.0) {
        const Vec3 y1 = from + d * (-b - std::sqrt(disc)), n1 = (y1 - centre) / kR;
        const double c1 = -dot(d, n1), s2 = (eo / ei) * (eo / ei) * (1.0 - c1 * c1);
        const Vec3 t = d * (eo / ei) + n1 * ((eo / ei) * c1 - std::sqrt(1.0 - s2));
        const Vec3 y2 = y1 + t * (-2.0 * dot(y1 - centre, t)), n2 = (y2 - centre) / kR;
        const double c2 = dot(t, n2), s3 = (ei / eo) * (ei / eo) * (1.0 - c2 * c2);
        if (s3 < 1.0) {
          const Vec3 out = t * (ei / eo) + n2 * (std::sqrt(1.0 - s3) - (ei / eo) * c2);
          if (dot(to - y2, out) > 0.0) side = dot(cross(out, to - y2), up);
        }
      }
      if (j > 0 && last != 0.0 && side != 0.0 && (last < 0.0) != (side < 0.0)) ++crossings;
      last = side;
    }
    if (!grazing) {
      EXPECT_EQ(found.count, crossings) << "k " << k;
      ++checked;
    }
    total += found.count;
  }
  std::printf("sphere passages: %d paths for 300 pairs (%d counted by tracing), worst |η u_t - η' v_t| %.2e\n", total,
              checked, worst);
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(checked, 250);
}

// The caustic under a clear glass ball lit by a point lamp (two crossings, which the path tracer
// now connects through from the floor) against the light tracer, which reaches it from the lamp:
// the floor's mean in the ball's shadow and around it, within 4 standard errors (each from the
// seeds' spread). Paths reflected inside the ball are the light tracer's alone: F·(1 − F)² of
// the light through it, about 4 %, is the tolerance's scale, so the ball is strongly absorbing
// (T² ≈ 0.1 on two chords: 0.4 %). Without the connection the shadow is black to the path tracer
// (no strategy of its meets a point lamp through glass); with one of the two paths through each
// point left out, it is about half as bright.
// A diffuse floor under one glass object `glass` (its JSON) of the absorbing glass, seen from
// above, lit by a point lamp at (0.1, 0.1, 0.01) or, with lamp_radius_m > 0, a spherical lamp
// there of that radius and emission scale `lamp_scale`.
std::string floor_under_glass(const char* integrator, int spp, const char* glass, double lamp_radius_m = 0.0,
                              double lamp_scale = 0.0, const char* lights = nullptr) {
  const std::string sphere_lamp = fmt::format(R"(,
      {{"name": "lamp", "shape": {{"type": "sphere", "radius": {}}}, "transform": [{{"translate": [0.1, 0.1, 0.01]}}],
       "emission": {{"spectrum": "D65", "scale": {}}}}})",
                                              lamp_radius_m, lamp_scale);
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0.3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
               "width": 0.12, "resolution": [24, 24]}},
    "render": {{"integrator": "{}", "spectral": "full", "spp": {}, "max_depth": 16, "seed": 1}},
    "world_medium": "vacuum",
    "media": {{"glass": {{"ior": 1.5, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [380, 780],
                                                     "value": [20, 30]}}}}}},
    "objects": [
      {{"name": "floor", "shape": {{"type": "quad", "size": [1, 1]}}, "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}],
        "material": {{"type": "diffuse", "reflectance": 0.8}}}},
      {}{}
    ],
    {}
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                     integrator, spp, glass, lamp_radius_m > 0.0 ? sphere_lamp : "",
                     lights           ? lights
                     : lamp_radius_m > 0.0
                         ? ""
                         : R"("lights": [{"type": "point", "position": [0.1, 0.1, 0.01], "spectrum": "D65", "scale": 0.02}],)");
}

std::string caustic_scene(const char* integrator, int spp, const char* lamp) {
  return floor_under_glass(integrator, spp, R"({"name": "ball", "shape": {"type": "sphere", "radius": 0.02},
        "transform": [{"translate": [0, 0.03, 0]}], "inside": "glass"})",
                           lamp[0] == 'p' ? 0.0 : 0.012, 40.0);
}

// The floor where the camera above does not see the ball (the light tracer cannot connect through
// it): the shadow and the caustic beside it (x < −r, the lamp is at +x), and the lit floor
// beyond (x > r); each region's mean over kSeeds seeds, and its standard error from their spread
// (with 4, a heavy-tailed estimate's spread came out 10 times too small).
constexpr int kSeeds = 8;
enum class Region { shadow, lit, ball };
void expect_floor_agrees(const std::vector<Film>& a, const std::vector<Film>& b, const char* what,
                         bool ball_too = false, bool rod = false) {
  auto region_means = [rod](const std::vector<Film>& films, int c, Region region) {
    std::vector<double> means;
    for (const Film& f : films) {
      double sum = 0.0;
      int n = 0;
      for (int j = 0; j < f.height; ++j)
        for (int i = 0; i < f.width; ++i) {
          const double x = (i + 0.5) / f.width - 0.5, z = (j + 0.5) / f.height - 0.5;  // in widths (0.12 m)
          const double r = std::hypot(x, z);  // the ball: radius 0.02 or 0.025 m, 0.17 or 0.21 widths
          // (A rod along z over the floor's middle: the floor beyond it either side in x.)
          const bool in = rod ? std::abs(x) >= 0.22 && (region == Region::shadow ? x < 0.0 : x > 0.0)
                          : region == Region::ball ? r < 0.16
                                                   : r >= 0.22 && (region == Region::shadow ? x < -0.05 : x > 0.05);
          if (!in) continue;
          sum += f.rgb_at(i, j)[c], ++n;
        }
      means.push_back(sum / n);
    }
    return test::mean_estimate(means);
  };
  std::vector<Region> regions{Region::shadow, Region::lit};
  if (ball_too) regions.push_back(Region::ball);
  for (const Region region : regions)
    for (int c = 0; c < 3; c += 2) {
      const test::Estimate ea = region_means(a, c, region), eb = region_means(b, c, region);
      const double se = std::hypot(ea.standard_error, eb.standard_error);
      const char* name = region == Region::shadow ? "shadow side" : region == Region::lit ? "lit side" : "ball";
      std::printf("%s, %s ch %d: %.5f ± %.5f against %.5f ± %.5f\n", what, name, c, ea.mean, ea.standard_error, eb.mean,
                  eb.standard_error);
      EXPECT_LT(se, 0.02 * eb.mean) << what << ": too noisy for the test to catch an 8 % error";
      EXPECT_NEAR(ea.mean, eb.mean, 4.0 * se) << what << " " << name << " ch " << c;
    }
}

TEST(ManifoldNextEvent, CausticUnderAGlassBallFromAPointLampMatchesTheLightTracer) {
  const auto path = test::render_seeds(parse_scene(caustic_scene("path", 16, "point"), "caustic.json"), kSeeds, 1);
  const auto light = test::render_seeds(parse_scene(caustic_scene("light", 128, "point"), "caustic.json"), kSeeds, 1);
  expect_floor_agrees(path, light, "point-lamp caustic, path against light");
}

// The same ball under a sun from the point lamp's direction (travelling along (−0.1, −0.07,
// −0.01)): the floor's shadow and the caustic in it, which the path tracer reaches through the
// ball in and out (manifold.h: sphere_passage_towards, beam_tube), against the light tracer, whose
// rays from the sun refract through the ball. Without the connection the shadow is black to the
// path tracer (a sun's light through glass came through one flat face only).
TEST(ManifoldNextEvent, CausticUnderAGlassBallFromASunMatchesTheLightTracer) {
  constexpr const char* kSun =
      R"("lights": [{"type": "distant", "direction": [-0.1, -0.07, -0.01], "spectrum": "D65", "scale": 2}],)";
  constexpr const char* kBall = R"({"name": "ball", "shape": {"type": "sphere", "radius": 0.02},
        "transform": [{"translate": [0, 0.03, 0]}], "inside": "glass"})";
  const auto path = test::render_seeds(parse_scene(floor_under_glass("path", 16, kBall, 0.0, 0.0, kSun), "sun.json"), kSeeds, 1);
  const auto light = test::render_seeds(parse_scene(floor_under_glass("light", 1024, kBall, 0.0, 0.0, kSun), "sun.json"), kSeeds, 1);
  expect_floor_agrees(path, light, "sun caustic under a ball, path against light");
}

// The same floor under a clear glass rod (an exact cylinder 20 mm in radius along z, 300 mm long,
// its axis 30 mm up; the same absorbing glass) lit by the same point lamp: the rod's shadow and the
// caustic line its lens draws in it (the rod focuses 1.5 radii from its axis, near the floor) fall
// at x < −0.22 widths, beside the part of the floor the camera sees through the rod. The path
// tracer's connections through the side in and out (cylinder_passage_points) against the light
// tracer, as for the ball. Without them the shadow side reads 0.0008 where the light tracer reads
// 0.063 (the glass absorbs, as the ball's, so that the light reflected inside the rod, which only
// the light tracer carries, stays far below the tolerance). The floor lies beyond the rod's focus, so each point has one path (the
// pairs near a caustic's fold are the unit test's).
std::string rod_scene(const char* integrator, int spp, bool spherical_lamp = false) {
  return floor_under_glass(integrator, spp, R"({"name": "rod", "shape": {"type": "cylinder", "radius": 0.02, "height": 0.3},
        "transform": [{"translate": [0, -0.15, 0]}, {"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.03, 0]}],
        "inside": "glass"})",
                           spherical_lamp ? 0.008 : 0.0, 90.0);
}

TEST(ManifoldNextEvent, CausticUnderAGlassRodFromAPointLampMatchesTheLightTracer) {
  const auto path = test::render_seeds(parse_scene(rod_scene("path", 16), "rod.json"), kSeeds, 1);
  const auto light = test::render_seeds(parse_scene(rod_scene("light", 128), "rod.json"), kSeeds, 1);
  expect_floor_agrees(path, light, "point-lamp caustic under a rod, path against light", false, true);
}

// The same rod under a spherical lamp (8 mm, small seen from the rod: next-event estimation goes
// on through the rod's side to the point it drew, area_light_through_cylinder, weighted against the
// walk's own paths through the side, CylinderTrail) against the light tracer, as for the point
// lamp. The white furnace with cylinders checks that each path is counted once; this, the
// connection's value (a tube, a Fresnel factor or a density wrong shifts the shadow side, where
// nearly all the light comes through the rod). The walks alone are no reference here: the lamp is
// small, and at 1024 spp their shadow side was still 2.3 % noisy, where the connections' is 0.2 %
// at 16.
TEST(ManifoldNextEvent, CausticUnderAGlassRodFromASphericalLampMatchesTheLightTracer) {
  const auto path = test::render_seeds(parse_scene(rod_scene("path", 16, true), "rod.json"), kSeeds, 1);
  const auto light = test::render_seeds(parse_scene(rod_scene("light", 128, true), "rod.json"), kSeeds, 1);
  expect_floor_agrees(path, light, "spherical-lamp caustic under a rod, path against light", false, true);
}

// The same ball under a spherical lamp (an area light, drawn by area on the part of it that faces
// the ball): the path tracer's connections through the ball, weighted against its walks' own
// paths through it by MIS, against its walks alone (manifold off), which reach the lamp only where
// a BSDF direction refracts onto it. Same expectation: a walk that counted its paths in full
// beside the connections came out 18 % bright on the shadow side; one that dropped a path the
// connection misses (a reflection inside, three crossings) darker by its share. Near a caustic's
// fold the connection's values have a heavy tail (its ray tube diverges), so the spread of 4
// seeds understated its standard error 10-fold: 8 seeds of 64 samples.
TEST(ManifoldNextEvent, CausticUnderAGlassBallFromASphericalLampMatchesTheWalksAlone) {
  SceneDesc on = parse_scene(caustic_scene("path", 64, "sphere"), "caustic.json");
  SceneDesc off = on;
  off.render.manifold = false;
  off.render.spp = 256;
  expect_floor_agrees(test::render_seeds(on, kSeeds, 1), test::render_seeds(off, kSeeds, 1),
                      "spherical-lamp caustic, connections against walks");
}

// A ball of scattering medium (n = 1.33, the issue's σ_s 30/12/6 per m three times over, g 0.7,
// radius 25 mm: optical radius 2.25 in blue) close under a quad lamp `lamp_m` across (its radiance
// scaled to the same power), `ball` its shape.
SceneDesc scattering_ball_under_a_quad(bool manifold, int spp, double lamp_m, const char* ball) {
  return parse_scene(fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0.09, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
               "width": 0.12, "resolution": [24, 24]}},
    "render": {{"integrator": "path", "spectral": "full", "spp": {}, "max_depth": 64, "seed": 1, "manifold": {},
               "area_lamp_chains": true}},
    "world_medium": "vacuum",
    "media": {{"milky": {{"ior": 1.33, "scattering": {{"unit": "attenuation_per_m", "wavelength_nm": [450, 550, 650],
                         "value": [90, 36, 18], "phase": {{"type": "henyey_greenstein", "g": 0.7}}}}}}}},
    "objects": [
      {{"name": "floor", "shape": {{"type": "quad", "size": [1, 1]}}, "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}],
        "material": {{"type": "diffuse", "reflectance": 0.5}}}},
      {{"name": "ball", "shape": {{"type": "sphere", "radius": 0.025{}}}, "transform": [{{"translate": [0, 0.03, 0]}}],
        "inside": "milky"}},
      {{"name": "lamp", "shape": {{"type": "quad", "size": [{}, {}]}},
        "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [0.03, 0.1, 0]}}],
        "emission": {{"spectrum": "D65", "scale": {}}}}}
    ],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                                 spp, manifold ? "true" : "false", ball, lamp_m, lamp_m, 0.5 * 0.36 / (lamp_m * lamp_m)),
                     "milky.json");
}

// The exact ball under a large lamp (0.6 m), where the walk's own directions reach the lamp about as
// well as the connections do: every scattering event inside reaches it through one crossing, and
// the two are weighted by MIS. Connections against walks, as above, over the ball and the floor
// around it. A connection left unweighted (counted in full beside the walk's weighted share) came
// out 21 % bright over the ball; a walk left unweighted, 12 %.
TEST(ManifoldNextEvent, ScatteringBallUnderAQuadLampMatchesTheWalksAlone) {
  expect_floor_agrees(test::render_seeds(scattering_ball_under_a_quad(true, 32, 0.6, ""), kSeeds, 1),
                      test::render_seeds(scattering_ball_under_a_quad(false, 96, 0.6, ""), kSeeds, 1),
                      "scattering ball under a quad lamp, connections against walks", true);
}

// The same ball a smooth-shaded mesh (64 segments) under a lamp 0.2 m across: its scattering events
// reach the lamp through chains of one mesh face (area_light_through_chain, asked for: the lamp is
// too large for it by default), weighted against the walks that refract onto it (ChainTrail), and
// the floor under the ball through two. A walk left unweighted read 20 % bright over the ball (1.43
// against 1.19 in red), a connection left unweighted 40 %; both fail it on the floor too. About 5 s
// on an idle core: `long` (the exact ball above, and the mesh chains of the lit tumbler's walls,
// stay in the suite).
TEST(ManifoldNextEventLong, ScatteringMeshBallUnderAQuadLampMatchesTheWalksAlone) {
  const char* mesh = R"(, "tessellate": true, "segments": 64)";
  expect_floor_agrees(test::render_seeds(scattering_ball_under_a_quad(true, 64, 0.2, mesh), kSeeds, 1),
                      test::render_seeds(scattering_ball_under_a_quad(false, 128, 0.2, mesh), kSeeds, 1),
                      "smooth-shaded scattering ball under a quad lamp, chains against walks", true);
}

// The connections draw from a stream of their own, seeded from the pixel sample's generator: the
// image is the same bit for bit at 1 and 2 threads.
TEST(ManifoldNextEvent, TheSameImageAtAnyThreadCount) {
  const SceneDesc desc = parse_scene(caustic_scene("path", 4, "sphere"), "caustic.json");
  const Film one = test::render_desc(desc, 1), two = test::render_desc(desc, 2);
  ASSERT_EQ(one.rgb.size(), two.rgb.size());
  EXPECT_TRUE(one.rgb == two.rgb);
  double sum = 0.0;
  for (const float value : one.rgb) sum += value;
  EXPECT_GT(sum, 0.0);
}

// A white furnace lit by lamps: inside a closed box whose walls are lamps of radiance 1 (two-sided
// quads, D65 at Y = 1: linear sRGB (1, 1, 1)), a white diffuse ball (reflectance 1), a clear glass
// ball and a glass ball of a medium that scatters without absorbing neither absorb nor emit, so
// every pixel is 1. The diffuse ball and the scattering events reach the walls through the glass
// both by connections and by the walk's own directions, weighted by MIS: weights that did not sum
// to 1 would show. Within 1 % and 3 standard errors, in full and hero modes. `balls` is the glass
// balls' shape: exact spheres (casters, crossed twice and once) or smooth-shaded meshes (chains of
// mesh faces: two crossings, one).
// `objects`: the glass in the furnace (a clear ball of glass and a ball of a scattering liquid, as
// `balls` shapes them, unless given).
void expect_white_furnace_of_lamps(const char* balls, const char* what, const char* objects = nullptr) {
  const std::string glass = objects ? std::string(objects) : fmt::format(R"(,
      {{"name": "clear", "shape": {{"type": "sphere", "radius": 0.03{}}}, "transform": [{{"translate": [0.0, -0.03, -0.05]}}],
        "inside": "glass"}},
      {{"name": "milky", "shape": {{"type": "sphere", "radius": 0.025{}}}, "transform": [{{"translate": [0.05, -0.02, 0]}}],
        "inside": "milky"}})", balls, balls);
  for (const char* mode : {"full", "hero"}) {
    const Film f = test::render_text(fmt::format(R"({{
    "camera": {{"position": [0, 0.02, 0.16], "look_at": [0, 0, 0], "fov_deg": 50, "resolution": [16, 12]}},
    "render": {{"integrator": "path", "spectral": "{}", "spp": 256, "max_depth": 256, "seed": 3,
               "area_lamp_chains": true}},
    "world_medium": "vacuum",
    "media": {{"glass": {{"ior": 1.5}},
              "milky": {{"ior": 1.33, "scattering": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                         "value": [60, 20], "phase": {{"type": "henyey_greenstein", "g": 0.5}}}}}}}},
    "objects": [
      {{"name": "walls", "shape": {{"type": "box", "size": [0.4, 0.4, 0.4]}},
        "emission": {{"spectrum": "D65", "scale": 1, "two_sided": true}}}},
      {{"name": "white", "shape": {{"type": "sphere", "radius": 0.025}}, "transform": [{{"translate": [-0.05, -0.03, 0]}}],
        "material": {{"type": "diffuse", "reflectance": 1.0}}}}{}
    ],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                                                 mode, glass));
    for (int c = 0; c < 3; ++c) {
      const test::Estimate e = test::channel_estimate(f, c, 0, 0, f.width, f.height);
      std::printf("furnace of lamps with %s (%s) ch %d: %.5f ± %.5f\n", what, mode, c, e.mean, e.standard_error);
      EXPECT_NEAR(e.mean, 1.0, 0.01) << what << ", " << mode << " ch " << c;
      EXPECT_LT(3.0 * e.standard_error, 0.01) << mode << " ch " << c << ": too few samples for the tolerance";
    }
  }
}

// Exact spheres: a walk left unweighted read 1.015–1.022, a connection left unweighted 1.024–1.032.
TEST(ManifoldNextEvent, WhiteFurnaceOfLampsWithCasters) { expect_white_furnace_of_lamps("", "casters"); }

// Smooth-shaded tessellated spheres (48 segments): the walls' points drawn for the straight line,
// hidden by the glass, are reached through chains of mesh faces (area_light_through_chain; the walls
// are far too large for that by default, so the scene asks for it), and the walks that refract onto
// a wall are weighted against them (ChainTrail). Measured: a walk left
// unweighted read 1.015–1.022, a connection left unweighted 1.026–1.031, both weighted 0.9996–0.9997 (full).
TEST(ManifoldNextEvent, WhiteFurnaceOfLampsWithChains) {
  expect_white_furnace_of_lamps(R"(, "tessellate": true, "segments": 48)", "chains");
}

// Exact cylinders: a lying rod of clear glass in front of the white ball, a standing column of the
// scattering liquid and, behind the rod, the clear ball (a caster). The walls' points drawn for the
// straight line, hidden by a cylinder's side, are reached through it (area_light_through_cylinder,
// once from inside the column, in and out through the rod; the scene asks for it, as for the
// chains), and the walks that refract onto a wall through the side are weighted against them
// (CylinderTrail), except where the ball lies across the straight segment and next-event
// estimation draws nothing there.
TEST(ManifoldNextEvent, WhiteFurnaceOfLampsWithCylinders) {
  expect_white_furnace_of_lamps("", "cylinders", R"(,
      {"name": "rod", "shape": {"type": "cylinder", "radius": 0.015, "height": 0.16},
       "transform": [{"translate": [0, -0.08, 0]}, {"rotate_deg": [90, [0, 0, 1]]}, {"translate": [0, -0.01, 0.04]}],
       "inside": "glass"},
      {"name": "clear", "shape": {"type": "sphere", "radius": 0.03}, "transform": [{"translate": [0.0, -0.03, -0.05]}],
       "inside": "glass"},
      {"name": "column", "shape": {"type": "cylinder", "radius": 0.02, "height": 0.08},
       "transform": [{"translate": [0.05, -0.05, -0.01]}], "inside": "milky"})");
}

// Where a caster lies across the straight segment from a vertex to the lamp point, next-event
// estimation draws no shadow ray and so no connection through a rod either (direct_light.h:
// caster_between); the walk's path through the rod to that point must then keep all its weight
// (cylinder_path_densities: no connection density). A rod along z, a spherical lamp beyond it, and
// (in the second scene, listed last so that the ids stay) a glass ball across the straight
// segment: the walk's path through the rod, solved in the first, gets a connection density there
// and none in the second. Before, the walk asked only for the first surface (the rod) and gave
// away a share of the path that no connection carried.
TEST(ManifoldNextEvent, NoConnectionThroughARodWhereABallLiesAcrossTheStraightSegment) {
  using namespace manifold_detail;
  auto scene = [](bool ball) {
    return compile(parse_scene(fmt::format(R"({{
    "camera": {{"position": [0, 0, 1], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [4, 4]}},
    "render": {{"integrator": "path"}},
    "world_medium": "vacuum",
    "media": {{"glass": {{"ior": 1.5}}}},
    "objects": [
      {{"name": "rod", "shape": {{"type": "cylinder", "radius": 0.01, "height": 0.2}},
        "transform": [{{"translate": [0, -0.1, 0]}}, {{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [0, 0.045, 0]}}],
        "inside": "glass"}},
      {{"name": "lamp", "shape": {{"type": "sphere", "radius": 0.01}}, "transform": [{{"translate": [0.11, 0.16, 0]}}],
        "emission": {{"spectrum": "D65", "scale": 1}}}}{}
    ],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                                           ball ? R"(,
      {"name": "ball", "shape": {"type": "sphere", "radius": 0.02}, "transform": [{"translate": [0.05, 0.1, 0]}],
       "inside": "glass"})"
                                                : ""),
                               "rod.json"));
  };
  const RenderScene clear = scene(false), blocked = scene(true);
  ASSERT_EQ(blocked.casters.size(), 1u);
  const Vec3 x{-0.05, 0.0, 0.002}, centre{0.11, 0.16, 0.0};
  const Vec3 q = centre - normalize(centre - x) * 0.01;  // the lamp's point facing x
  EXPECT_FALSE(caster_between(clear, x, q));
  EXPECT_TRUE(caster_between(blocked, x, q));
  std::uint64_t rays = 0;
  const auto first = first_surface(clear, x, nullptr, 0, q, rays);
  ASSERT_TRUE(first);
  const auto f = smooth_interface(clear, first->hit, first->seen);
  ASSERT_TRUE(f && f->shape == Interface::Shape::cylinder);
  const Paths p = solve(*f, x, q, 1.0, 1.5);
  ASSERT_GE(p.count, 1);
  ASSERT_EQ(p.crossings, 2);
  const std::array<Vec3, 2>& ys = p.crossing[0];
  const Vec3 d = normalize(q - ys[1]);
  const auto hit = clear.rays.intersect(Ray{ys[1] + d * 1e-6, d, 1.0});
  ASSERT_TRUE(hit);
  ASSERT_EQ(clear.surfaces[hit->geometry].kind, SurfaceKind::emitter);
  const std::span<const Vec3> points(ys.data(), 2);
  const CasterPathDensities there = cylinder_path_densities(clear, x, nullptr, 0, points, *hit, rays);
  const CasterPathDensities behind_ball = cylinder_path_densities(blocked, x, nullptr, 0, points, *hit, rays);
  std::printf("the walk's path through the rod: connection density %.4g without the ball, %.4g with it\n",
              there.connection, behind_ball.connection);
  EXPECT_GT(there.connection, 0.0);
  EXPECT_EQ(behind_ball.connection, 0.0);
}

// Which lamps next-event estimation reaches through chains of mesh faces unless the scene says
// (Surface::small_lamp, SceneView::lamp_through_chains): those that subtend less than
// kLampChainSolidAngle (0.05 sr) seen from the nearest smooth refracting mesh. The lit tumbler's
// 20 mm softbox 150 mm away (about 0.02 sr) and 5 mm bulb (0.004 sr) yes; a 100 mm panel 3 mm from a
// glass tank (the sunset-in-a-tank showcase's case) no; a 5 mm bulb at the centre of a 100 mm mesh
// globe (0.008 sr seen from its wall) yes, inside an exact globe (a caster's, not a chain's) no.
// `area_lamp_chains` true or false in the render settings: every lamp, or none.
TEST(ManifoldNextEvent, AreaLampChainsRunForLampsSmallSeenFromTheGlass) {
  auto small = [](const std::string& lamps, const char* glass) {
    const RenderScene s = compile(parse_scene(fmt::format(R"({{
    "camera": {{"position": [0, 0.06, 0.26], "look_at": [0, 0.045, 0], "fov_deg": 22, "resolution": [8, 8]}},
    "render": {{"integrator": "path"}},
    "media": {{"glass": {{"ior": 1.52}}}},
    "objects": [{}{}]
  }})",
                                                   glass, lamps),
                                       "lamps.json"));
    std::vector<bool> out;
    for (const Surface& f : s.surfaces)
      if (f.kind == SurfaceKind::emitter) out.push_back(f.small_lamp);
    EXPECT_EQ(s.small_lamps, std::find(out.begin(), out.end(), true) != out.end());
    return out;
  };
  const char* tumbler = R"({"name": "tumbler", "shape": {"type": "vessel", "wall": "2 mm", "segments": 64,
      "profile": [[0, 0], ["30 mm", 0], ["32 mm", "90 mm"]]}, "inside": "glass"})";
  const std::string softbox_and_bulb = R"(,
      {"name": "softbox", "shape": {"type": "quad", "size": ["20 mm", "20 mm"]},
       "transform": [{"rotate_deg": [90, [0, 1, 0]]}, {"translate": ["-150 mm", "30 mm", "40 mm"]}],
       "emission": {"spectrum": "D65", "two_sided": true}},
      {"name": "bulb", "shape": {"type": "sphere", "radius": "5 mm"}, "transform": [{"translate": ["150 mm", "60 mm", "-60 mm"]}],
       "emission": {"spectrum": "A"}})";
  EXPECT_EQ(small(softbox_and_bulb, tumbler), (std::vector<bool>{true, true}));
  const char* tank = R"({"name": "tank", "shape": {"type": "box", "size": ["320 mm", "90 mm", "90 mm"]}, "inside": "glass"})";
  const std::string panel = R"(,
      {"name": "panel", "shape": {"type": "quad", "size": ["100 mm", "100 mm"]},
       "transform": [{"rotate_deg": [90, [0, 1, 0]]}, {"translate": ["-163 mm", 0, 0]}], "emission": {"spectrum": "D65"}})";
  EXPECT_EQ(small(panel, tank), (std::vector<bool>{false}));
  const char* globe = R"({"name": "globe", "shape": {"type": "sphere", "radius": "50 mm", "tessellate": true}, "inside": "glass"})";
  const std::string bulb = R"(,
      {"name": "bulb", "shape": {"type": "sphere", "radius": "5 mm"}, "emission": {"spectrum": "A"}})";
  EXPECT_EQ(small(bulb, globe), (std::vector<bool>{true}));
  const char* exact_globe = R"({"name": "globe", "shape": {"type": "sphere", "radius": "50 mm"}, "inside": "glass"})";
  EXPECT_EQ(small(bulb, exact_globe), (std::vector<bool>{false}));
  // Inside an exact glass tube (50 mm in radius, 200 mm long, the bulb halfway up its axis): from
  // its wall, 0.03 sr (measured to its bounding box, which holds the bulb, it read as large).
  const char* tube = R"({"name": "tube", "shape": {"type": "cylinder", "radius": "50 mm", "height": "200 mm"},
      "transform": [{"translate": [0, "-100 mm", 0]}], "inside": "glass"})";
  EXPECT_EQ(small(bulb, tube), (std::vector<bool>{true}));
  // The render's setting over the compiled flags.
  RenderScene s;
  s.surfaces.resize(2);
  s.surfaces[1].small_lamp = true;
  const SpectralTables<3> tables(s.spectra, SpectralMode::rgb3);
  const Camera camera(CameraDesc{});
  SceneView<3> v{s, tables, camera};
  EXPECT_FALSE(v.lamp_through_chains(0));
  EXPECT_TRUE(v.lamp_through_chains(1));
  v.area_lamp_chains = true;
  EXPECT_TRUE(v.lamp_through_chains(0));
  v.area_lamp_chains = false;
  EXPECT_FALSE(v.lamp_through_chains(1));
}

}  // namespace
}  // namespace bouguer
