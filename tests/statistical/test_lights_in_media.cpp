// Lights inside media carry the right flux out of them (docs/rendering.md, "Radiance across a
// refraction"). A point light at the centre of an absorbing glass sphere above a white floor: its
// light leaves radially, at normal incidence, so every direction keeps the fraction
//   (1 − R)·e^(−σ_a r) / (1 − R·e^(−2σ_a r)),   R = ((n − 1)/(n + 1))²,
// the sum over the light emitted that way and the light emitted the opposite way, reflected back
// through the centre. The floor must receive the bare light times that, for every estimator that
// reaches a point light through glass. Before the radiance convention was fixed, the light tracer
// gave about n² times as much.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <string_view>
#include <vector>

#include "bouguer/render/film.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr double kRadius_m = 0.05, kHeight_m = 0.2, kFloorHalf_m = 0.5;

// `sphere`: the sphere's medium (index, σ_a per m), none for the bare light. The camera looks
// straight down on the floor (orthographic), 32×32 pixels of 1/32 m.
std::string sphere_scene(const char* integrator, int spp, double n, double sigma_a_per_m, bool sphere,
                         std::uint64_t seed, int segments = 256) {
  const std::string glass = sphere ? fmt::format(R"(,
      {{"name": "glass", "shape": {{"type": "sphere", "radius": {}, "segments": {}}},
        "transform": [{{"translate": [0, {}, 0]}}], "inside": "glass"}})",
                                                 kRadius_m, segments, kHeight_m)
                                   : "";
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
               "width": {}, "resolution": [32, 32]}},
    "render": {{"integrator": "{}", "spectral": "rgb3", "spp": {}, "max_depth": 64, "seed": {}}},
    "media": {{"glass": {{"ior": {}, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [300, 900],
                                                  "value": [{}, {}]}}}}}},
    "objects": [
      {{"name": "floor", "shape": {{"type": "quad", "size": [{}, {}]}}, "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}],
        "material": {{"type": "diffuse", "reflectance": 0.8}}}}{}
    ],
    "lights": [{{"type": "point", "position": [0, {}, 0], "spectrum": "D65", "scale": 0.01}}]
  }})",
                     2.0 * kFloorHalf_m, integrator, spp, seed, n, sigma_a_per_m, sigma_a_per_m, 2.0 * kFloorHalf_m,
                     2.0 * kFloorHalf_m, glass, kHeight_m);
}

double sphere_transmission(double n, double sigma_a_per_m) {
  const double r = (n - 1.0) / (n + 1.0), reflectance = r * r;
  const double t = std::exp(-sigma_a_per_m * kRadius_m);
  return (1.0 - reflectance) * t / (1.0 - reflectance * t * t);
}

// Per channel: the sum over the pixels that see the floor outside the sphere's outline (seen
// from above, the sphere hides |x|, |z| ≤ r) of two renders' mean, and the variance of that sum
// from each pixel's two seeds: a pixel's (a − b)²/2 estimates its variance, and the sum of the
// means has Σ (a − b)²/4 (the pixels are independent, so this has as many degrees of freedom as
// there are pixels, where the two image sums' difference would have one).
struct FloorSums {
  double rgb[3] = {0.0, 0.0, 0.0}, variance[3] = {0.0, 0.0, 0.0};
};

// vcm's pixels are not independent (every pixel of an iteration merges the same photons), so its
// sums come from kVcmSeeds renders of 2·spp / kVcmSeeds iterations each (as many in all as the
// other estimators' two renders): the mean of their sums and
// the variance of that mean from their spread (K − 1 degrees of freedom).
constexpr int kVcmSeeds = 16;

FloorSums floor_sums(const Film& a, const Film& b);

FloorSums floor_sums_over_seeds(const std::vector<Film>& films) {
  std::array<std::vector<double>, 3> sums;
  for (const Film& f : films) {
    const FloorSums one = floor_sums(f, f);
    for (int c = 0; c < 3; ++c) sums[c].push_back(one.rgb[c]);
  }
  FloorSums s;
  for (int c = 0; c < 3; ++c) {
    const test::Estimate e = test::mean_estimate(sums[c]);
    s.rgb[c] = e.mean;
    s.variance[c] = e.standard_error * e.standard_error;
  }
  return s;
}

FloorSums floor_sums(const Film& a, const Film& b) {
  FloorSums s;
  const double pixel_m = 2.0 * kFloorHalf_m / a.width;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const double px = -kFloorHalf_m + (x + 0.5) * pixel_m, pz = -kFloorHalf_m + (y + 0.5) * pixel_m;
      if (std::abs(px) < kRadius_m + pixel_m && std::abs(pz) < kRadius_m + pixel_m) continue;
      const Vec3f va = a.rgb_at(x, y), vb = b.rgb_at(x, y);
      for (int c = 0; c < 3; ++c) {
        s.rgb[c] += 0.5 * (double(va[c]) + double(vb[c]));
        s.variance[c] += 0.25 * (double(va[c]) - double(vb[c])) * (double(va[c]) - double(vb[c]));
      }
    }
  return s;
}

// The floor under the sphere against the bare light, per channel, for one estimator: within 1 %,
// with the ratio's standard error (from the pixels' own noise: the bare floor's, which the path
// tracer renders for every estimator, and the lit one's; vcm's lit one from its seeds) under 0.25 %,
// so that the 1 % holds 4 of them and a flux off by 2 % (a lost (1 − R), a radiance across the
// refraction off by a power of n) fails.
void expect_sphere_energy(const char* integrator, double n, double sigma_a_per_m, int spp) {
  auto lit_sums = [&](std::uint64_t seed) {
    if (std::string_view(integrator) == "vcm")
      return floor_sums_over_seeds(test::render_seeds(
          parse_scene(sphere_scene(integrator, 2 * spp / kVcmSeeds, n, sigma_a_per_m, true, seed), "sphere.json"),
          kVcmSeeds, seed));
    return floor_sums(test::render_text(sphere_scene(integrator, spp, n, sigma_a_per_m, true, seed)),
                      test::render_text(sphere_scene(integrator, spp, n, sigma_a_per_m, true, seed + 1)));
  };
  // The bare light by the path tracer, whatever estimator is under test: its floor is next-event
  // estimation of a point lamp on a diffuse quad, noise only from where the samples fall in a
  // pixel, so the ratio's noise is the lit render's alone, and an estimator whose flux is off
  // by the same factor with the sphere and without it fails too.
  const FloorSums bare = floor_sums(test::render_text(sphere_scene("path", 16, n, sigma_a_per_m, false, 1)),
                                    test::render_text(sphere_scene("path", 16, n, sigma_a_per_m, false, 2)));
  const FloorSums lit = lit_sums(3);
  const double expected = sphere_transmission(n, sigma_a_per_m);
  for (int c = 0; c < 3; ++c) {
    ASSERT_GT(bare.rgb[c], 0.0);
    const double ratio = lit.rgb[c] / bare.rgb[c] / expected;
    const double se = ratio * std::sqrt(lit.variance[c] / (lit.rgb[c] * lit.rgb[c]) +
                                        bare.variance[c] / (bare.rgb[c] * bare.rgb[c]));
    std::printf("%s, n = %.1f, σ_a = %.0f/m, channel %d: floor / (bare × closed form) = %.4f ± %.4f\n", integrator, n,
                sigma_a_per_m, c, ratio, se);
    EXPECT_LT(se, 0.0025) << "too noisy to test at 1 %";
    EXPECT_NEAR(ratio, 1.0, 0.01) << integrator << " n " << n << " channel " << c;
  }
}

TEST(LightsInMedia, PointLightInAGlassSphereLightTracer) {
  for (const double n : {1.2, 1.5, 2.0}) expect_sphere_energy("light", n, 6.0, 512);
}

// The bidirectional estimator reaches the floor by light tracing and by connections from the
// floor to light-path vertices on the sphere; next-event estimation is blocked by the glass. At
// n = 2 only, where the radiance convention's n² is largest (the light tracer above takes all
// three: it is cheap, and it shares the convention's code with bdpt and vcm).
TEST(LightsInMedia, PointLightInAGlassSphereBidirectional) { expect_sphere_energy("bdpt", 2.0, 6.0, 512); }

// Vertex connection and merging adds merging on the floor to bdpt's strategies. Its error comes
// from 16 seeds (above): 0.18 % at 768 iterations a render (0.23 % when vcm's own bare floor, with
// its seeds' noise, was the reference; 0.31 % at 384).
TEST(LightsInMedia, PointLightInAGlassSphereVertexMerging) { expect_sphere_energy("vcm", 2.0, 6.0, 768); }

// An emitter immersed in a dielectric that does not absorb neither loses flux nor gains it: the
// same closed form at σ_a = 0 is exactly 1 (the reflected light leaves through the far side).
TEST(LightsInMedia, PointLightInClearGlassKeepsItsFlux) {
  expect_sphere_energy("light", 1.5, 0.0, 512);
}

}  // namespace
}  // namespace bouguer
