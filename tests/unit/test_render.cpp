// Renders of analytic scenes with stated tolerances.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>

#include "bouguer/materials/fresnel.h"
#include "bouguer/media/library.h"
#include "bouguer/render/render.h"
#include "bouguer/render/spectral_sampling.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "bouguer/spectra/cie.h"

namespace bouguer {
namespace {

// A slab of thickness d (10 cm square, n = 1.5, red glass or a probe absorber) in vacuum, seen
// straight down by an orthographic camera, lit from below by a D65 panel.
std::string slab_scene(double thickness_mm, const std::string& absorption, const char* spectral) {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                "width": "20 mm", "resolution": [4, 4]}},
    "render": {{"spectral": "{}", "spp": 1, "max_depth": 64}},
    "world_medium": "vacuum",
    "media": {{"glass": {{"ior": 1.5, "absorption": {}}}}},
    "objects": [
      {{"name": "slab", "shape": {{"type": "box", "size": ["100 mm", "{} mm", "100 mm"]}}, "inside": "glass"}},
      {{"name": "panel", "shape": {{"type": "quad", "size": [1, 1]}},
        "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}, {{"translate": [0, -0.2, 0]}}],
        "emission": {{"spectrum": "D65", "scale": 1.0}}}}
    ]
  }})",
                     spectral, absorption, thickness_mm);
}

Film render_text(const std::string& json, int threads = 1) {
  const RenderScene scene = compile(parse_scene(json, "test.json"));
  RenderOptions options;
  options.threads = threads;
  RenderStats stats;
  return render(scene, options, stats);
}

// The closed form T = (1−R)²τ / (1 − R²τ²), τ = exp(−σ_a d), in the mode's own wavelengths.
template <std::size_t N>
Vec3 slab_closed_form(const SpectralBasis<N>& basis, const Spectrum& sigma_a_per_m, double thickness_m) {
  const double r = fresnel_dielectric(1.0, 1.0, 1.5);
  const auto sigma = basis.at_wavelengths(sigma_a_per_m);
  auto l = basis.emission(named_illuminant("D65"));
  for (std::size_t i = 0; i < N; ++i) {
    const double tau = std::exp(-double(sigma[i]) * thickness_m);
    l[i] = static_cast<float>(l[i] * (1 - r) * (1 - r) * tau / (1 - r * r * tau * tau));
  }
  return basis.to_linear_srgb(l);
}

void expect_within_half_percent(const Vec3f& got, const Vec3& expected, const std::string& what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 0.005 * std::abs(expected[c]) + 1e-6) << what << " ch " << c;
}

TEST(Render, BacklitSlabMatchesTheClosedFormInBothModes) {
  const Spectrum red = find_library_material("red-glass")->sigma_a_per_m;
  for (const double mm : {0.5, 2.0, 6.0, 12.0}) {
    const std::string absorption = R"({"library": "red-glass"})";
    const Film full = render_text(slab_scene(mm, absorption, "full"));
    expect_within_half_percent(full.rgb_at(1, 2), slab_closed_form(make_full_basis(), red, mm * 1e-3),
                               fmt::format("full {} mm", mm));
    const Film rgb3 = render_text(slab_scene(mm, absorption, "rgb3"));
    expect_within_half_percent(rgb3.rgb_at(1, 2), slab_closed_form(make_rgb3_basis(), red, mm * 1e-3),
                               fmt::format("rgb3 {} mm", mm));
  }
}

TEST(Render, DoublingConcentrationEqualsDoublingThickness) {
  const std::string probe = R"({"unit": "absorbance_per_cm", "wavelength_nm": [380, 480, 580, 680, 780],
                                "value": [0.9, 0.5, 0.2, 0.1, 0.1], "concentration": %C%})";
  auto with = [&](const char* c) { return std::string(probe).replace(probe.find("%C%"), 3, c); };
  for (const char* mode : {"full", "rgb3"}) {
    const Film doubled_c = render_text(slab_scene(5.0, with("2.0"), mode));
    const Film doubled_d = render_text(slab_scene(10.0, with("1.0"), mode));
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(doubled_c.rgb_at(2, 2)[c], doubled_d.rgb_at(2, 2)[c]) << mode;
    const Film single = render_text(slab_scene(5.0, with("1.0"), mode));
    EXPECT_GT(single.rgb_at(2, 2).z, doubled_d.rgb_at(2, 2).z * 1.1) << mode;  // the test can fail
  }
}

// A scene with every code path: refraction, TIR, absorption, a diffuse floor lit by shadow rays.
TEST(Render, ThreadCountDoesNotChangeTheImage) {
  const std::string scene = R"({
    "camera": {"position": [0.05, 0.12, 0.1], "look_at": [0, 0, 0], "fov_deg": 35, "resolution": [48, 36]},
    "render": {"spp": 4, "seed": 3},
    "media": {"glass": {"absorption": {"library": "light-blue-glass"}}},
    "objects": [
      {"name": "gem", "shape": {"type": "brilliant", "diameter": "30 mm"}, "inside": "glass",
       "transform": [{"translate": [0, "10 mm", 0]}]},
      {"name": "floor", "shape": {"type": "quad", "size": [0.3, 0.3]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
       "material": {"type": "diffuse", "reflectance": 0.6}},
      {"name": "lamp", "shape": {"type": "disk", "radius": "30 mm"},
       "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0.05, 0.2, 0]}],
       "emission": {"spectrum": "A", "scale": 20}}
    ]
  })";
  const Film one = render_text(scene, 1);
  const Film two = render_text(scene, 2);
  EXPECT_EQ(one.rgb, two.rgb);
  double sum = 0;
  for (float v : one.rgb) sum += v;
  EXPECT_GT(sum, 0.0);
}

}  // namespace
}  // namespace bouguer
