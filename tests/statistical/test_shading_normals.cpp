// Shading normals (docs/rendering.md, "Shading normals"): the BSDF in the shading frame, the sides
// from the geometric normal, Veach's adjoint for light paths. Closed forms first (the adjoint
// identity, no leaks, the exact normals of surfaces of revolution), then renders.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <random>

#include "bouguer/core/error.h"
#include "bouguer/geometry/shapes.h"
#include "bouguer/integrators/events.h"
#include "bouguer/materials/surface_bsdf.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr std::size_t N = 3;

Vec3 uniform_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = 2.0 * u(rng) - 1.0, r = std::sqrt(1.0 - z * z), phi = 2.0 * kPi * u(rng);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// A shading normal tilted by `tilt_deg` from the geometric normal +z, about the y axis.
SurfaceEvent<N> tilted_event(const Bsdf<N>& bsdf, double tilt_deg) {
  const double t = tilt_deg * kPi / 180.0;
  SurfaceEvent<N> e{Frame(Vec3{std::sin(t), 0.0, std::cos(t)}), bsdf};
  e.ng = {0.0, 0.0, 1.0};
  e.medium_front = 0;
  e.medium_behind = 1;
  return e;
}

struct Bsdfs {
  DielectricAlbedo albedo = DielectricAlbedo::compute(0.3, 1.0, 1.5);
  std::vector<Bsdf<N>> all;
  Bsdfs() {
    SampledSpectrum<N> reflectance, n, k;
    reflectance.v = {0.8f, 0.5f, 0.2f};
    n.v = {0.2f, 0.9f, 1.1f};
    k.v = {3.9f, 2.4f, 2.2f};
    all = {DiffuseReflection<N>{reflectance}, ConductorReflection<N>{n, k, 1.0, 0.25},
           RoughDielectric{{{0.3}, 1.0, 1.5, &albedo}}, SmoothDielectric{1.0, 1.5}};
  }
};

// With shading normals the BSDF is not symmetric; the importance mode's correction makes it the
// adjoint of the geometric-measure BSDF: f*(a, b)/|b·n_g| = f(b, a)/|a·n_g| for every pair, which
// the local BSDFs' own adjoint (test_transport.cpp) turns into this identity only with the factor.
TEST(ShadingNormals, LightPathsUseTheAdjointOfTheShadedBsdf) {
  Bsdfs b;
  std::mt19937_64 rng(7);
  int compared = 0, corrected = 0;
  for (std::size_t i = 0; i + 1 < b.all.size(); ++i) {  // the smooth dielectric has no values to compare
    const SurfaceEvent<N> e = tilted_event(b.all[i], 25.0);
    for (int s = 0; s < 4000; ++s) {
      const Vec3 a = uniform_direction(rng), c = uniform_direction(rng);
      const SampledSpectrum<N> imp = e.eval(a, c, TransportMode::importance);
      const SampledSpectrum<N> rad = e.eval(c, a, TransportMode::radiance);
      const double lhs = imp[1] / std::abs(c.z), rhs = rad[1] / std::abs(a.z);
      ASSERT_NEAR(lhs, rhs, 1e-5 * std::max(1.0, std::abs(rhs))) << "bsdf " << i << " pair " << s;
      if (imp[1] > 0.0f) ++compared;
      // What the light path would carry without the correction: not the adjoint.
      const double raw = eval(e.bsdf, e.frame.to_local(a), e.frame.to_local(c), TransportMode::importance)[1] /
                         std::abs(c.z);
      if (imp[1] > 0.0f && std::abs(raw / rhs - 1.0) > 0.05) ++corrected;
    }
  }
  EXPECT_GT(compared, 4000);
  EXPECT_GT(corrected, compared / 4);
}

// No light leaks: a pair that is a reflection for one frame and a transmission for the other has
// no value, and sampling never returns one; every sample's side is the geometry's, so it travels in
// the medium medium_towards says, the one its lobe (reflected or transmitted) is meant for.
TEST(ShadingNormals, NoSampleCrossesTheGeometricSurfaceAgainstItsLobe) {
  Bsdfs b;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int killed = 0, kept = 0;
  for (const Bsdf<N>& bsdf : b.all) {
    const SurfaceEvent<N> e = tilted_event(bsdf, 30.0);
    const bool opaque = std::holds_alternative<DiffuseReflection<N>>(bsdf) ||
                        std::holds_alternative<ConductorReflection<N>>(bsdf);
    for (int s = 0; s < 20000; ++s) {
      Vec3 wo = uniform_direction(rng);
      if (opaque && wo.z < 0.0) wo = -wo;  // an opaque event's normals face wo
      if ((dot(wo, e.frame.n) > 0.0) != (wo.z > 0.0)) continue;  // surface_event falls back to n_g there
      const auto smp = e.sample(wo, u(rng), u(rng), u(rng), TransportMode::radiance);
      if (!smp) {
        ++killed;
        continue;
      }
      ++kept;
      const bool crosses = wo.z * smp->wi.z < 0.0;
      ASSERT_EQ(crosses, smp->transmitted) << "sample " << s;
      ASSERT_EQ(e.medium_towards(smp->wi), crosses ? (wo.z > 0 ? 1 : 0) : (wo.z > 0 ? 0 : 1));
      const Vec3 other = uniform_direction(rng);
      const bool shading_reflects = dot(wo, e.frame.n) * dot(other, e.frame.n) > 0.0;
      if (shading_reflects != (wo.z * other.z > 0.0)) {
        ASSERT_TRUE(e.eval(wo, other, TransportMode::radiance).is_zero()) << "sample " << s;
      }
    }
  }
  std::printf("samples the geometry refuses at a 30° tilt: %d of %d\n", killed, killed + kept);
  EXPECT_GT(killed, 0);
  EXPECT_GT(kept, killed);
}

// Surfaces of revolution carry the exact normal of the surface at each vertex.
TEST(ShadingNormals, RevolvedShapesCarryTheirExactNormals) {
  const double radius = 0.01;
  const Mesh sphere = make_shape(SphereShape{radius, 24, true}, "ball").front().mesh;
  ASSERT_EQ(sphere.normals.size(), sphere.positions.size());
  for (std::size_t i = 0; i < sphere.positions.size(); ++i)
    EXPECT_NEAR(length(sphere.normals[i] - sphere.positions[i] / radius), 0.0, 1e-12) << "vertex " << i;
  // A cylinder: radial normals on its side, ±y on its caps; the rims are creases (two vertices each).
  const Mesh can = make_shape(CylinderShape{radius, 0.02, 16, true}, "can").front().mesh;
  ASSERT_EQ(can.normals.size(), can.positions.size());
  int side = 0, caps = 0;
  for (std::size_t i = 0; i < can.positions.size(); ++i) {
    const Vec3 p = can.positions[i], n = can.normals[i];
    if (std::abs(n.y) == 1.0) {
      ++caps;
      EXPECT_TRUE(p.y == 0.0 ? n.y < 0.0 : n.y > 0.0) << "vertex " << i;
    } else {
      ++side;
      EXPECT_NEAR(length(n - Vec3{p.x, 0.0, p.z} / radius), 0.0, 1e-12) << "vertex " << i;
    }
  }
  EXPECT_EQ(side, 2 * 16);
  EXPECT_EQ(caps, 2 * 16 + 2);
  EXPECT_FALSE(closed_surface_problem(welded(can, 1e-12)));
  // A lathe's smooth profile: a quarter circle from the axis to the side, the normals the circle's.
  std::vector<std::array<double, 2>> dome;
  for (int i = 0; i <= 8; ++i) dome.push_back({radius * std::sin(kPi / 2 * i / 8), radius * std::cos(kPi / 2 * i / 8)});
  dome.push_back({radius, -radius});
  dome.push_back({0.0, -radius});
  const Mesh lathe = make_shape(LatheShape{dome, 32}, "dome").front().mesh;
  int on_dome = 0;
  for (std::size_t i = 0; i < lathe.positions.size(); ++i)
    if (lathe.positions[i].y > 1e-12 && lathe.positions[i].y < radius * std::cos(kPi / 16) + 1e-12) {
      ++on_dome;
      EXPECT_NEAR(length(lathe.normals[i] - lathe.positions[i] / radius), 0.0, 1e-12) << "vertex " << i;
    }
  EXPECT_EQ(on_dome, 7 * 32);
  EXPECT_FALSE(closed_surface_problem(welded(lathe, 1e-12)));
  // A cone's apex is a crease: one vertex per wedge, each with its wedge's normal.
  const Mesh cone = make_shape(LatheShape{{{0, 0}, {radius, 0}, {0, radius}}, 8}, "cone").front().mesh;
  int apex = 0;
  for (std::size_t i = 0; i < cone.positions.size(); ++i)
    if (cone.positions[i].y == radius) {
      ++apex;
      EXPECT_NEAR(cone.normals[i].y, std::sqrt(0.5), 1e-12);
    }
  EXPECT_EQ(apex, 8);
  EXPECT_THROW(make_shape(LatheShape{dome, 32, -1.0}, "dome"), Error);
}

// A diffuse quad whose OBJ normals lean 30° away from its face, lit by a point light: the path
// tracer (next-event estimation, radiance mode), the light tracer (importance mode, every path
// connected to the camera), bdpt and vcm must render the same image. Without the adjoint correction the light
// tracer's image is off by the mean of |wo·ns||wi·ng| / (|wo·ng||wi·ns|) over the quad (measured:
// −60 %, −0.178 ± 0.009); with it, −0.0007 ± 0.0005. Bdpt and vcm connect and merge with the same
// corrected BSDF.
TEST(ShadingNormals, PathAndLightTracersAgreeOnATiltedShadingNormal) {
  const auto dir = test::scratch_dir("ShadingNormals.Tilted");
  const double s = std::sin(kPi / 6), c = std::cos(kPi / 6);
  test::write_file(dir / "tilted.obj", fmt::format("v -0.02 -0.02 0\nv 0.02 -0.02 0\nv 0.02 0.02 0\nv -0.02 0.02 0\n"
                                                   "vn {0} 0 {1}\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n",
                                                   s, c));
  auto scene = [&](const char* integrator, int spp) {
    return fmt::format(R"({{
      "camera": {{"position": [-0.05, 0.01, 0.07], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [16, 16]}},
      "render": {{"integrator": "{}", "spectral": "rgb3", "spp": {}, "max_depth": 1}},
      "world_medium": "vacuum",
      "objects": [{{"name": "quad", "shape": {{"type": "mesh", "file": "{}"}},
                   "material": {{"type": "diffuse", "reflectance": 0.8}}}}],
      "lights": [{{"type": "point", "position": [0.04, 0.02, 0.05], "spectrum": "E", "scale": 0.01}}],
      "background": {{"spectrum": "E", "scale": 0.0}}
    }})",
                       integrator, spp, (dir / "tilted.obj").string());
  };
  const Film path = test::render_text(scene("path", 64));
  const double mean = test::channel_estimate(path, 1, 0, 0, path.width, path.height).mean;
  ASSERT_GT(mean, 0.0);
  for (const auto& [integrator, spp] : {std::pair{"light", 65536}, std::pair{"bdpt", 1024}, std::pair{"vcm", 1024}}) {
    const test::Estimate d = test::difference_estimate(path, test::render_text(scene(integrator, spp)), 1);
    std::printf("tilted normals: path %.5f, %s − path %+.5f ± %.5f\n", mean, integrator, d.mean, d.standard_error);
    EXPECT_LT(4.0 * d.standard_error, 0.02 * mean) << integrator;  // the test can tell a 2 % difference
    EXPECT_NEAR(d.mean, 0.0, 4.0 * d.standard_error) << integrator;
  }
}

// Energy through smooth-shaded glass: a 12- and a 24-segment tessellated glass ball (n = 1.5) in a
// white furnace. Shading normals make no light; paths whose sample the geometry refuses carry it
// away, at grazing angles on a strongly bent normal only: measured 0.85 % (12 segments), 0.42 %
// (24) and 0.08 % (48) of the image. The analytic ball and flat facets lose nothing.
TEST(ShadingNormals, SmoothShadedGlassBallInAWhiteFurnaceLosesLittle) {
  for (const int segments : {12, 24}) {
    const Film film = test::render_text(fmt::format(R"({{
      "camera": {{"position": [0, 0, 0.1], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [24, 24]}},
      "render": {{"integrator": "path", "spectral": "rgb3", "spp": 128, "max_depth": 200}},
      "world_medium": "vacuum",
      "media": {{"glass": {{"ior": 1.5}}}},
      "objects": [{{"name": "ball", "shape": {{"type": "sphere", "radius": "20 mm", "tessellate": true,
                   "segments": {}}}, "inside": "glass"}}],
      "background": {{"spectrum": "E", "scale": 1.0}}
    }})",
                                                    segments));
    const Film bare = test::render_text(R"({
      "camera": {"position": [0, 0, 0.1], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [4, 4]},
      "render": {"integrator": "path", "spectral": "rgb3", "spp": 1},
      "world_medium": "vacuum", "objects": [], "background": {"spectrum": "E", "scale": 1.0}
    })");
    const double background = bare.rgb_at(0, 0)[1];
    const test::Estimate e = test::channel_estimate(film, 1, 0, 0, film.width, film.height);
    const double loss = 1.0 - e.mean / background;
    std::printf("%d-segment smooth glass ball: %.3f %% lost (± %.3f %%)\n", segments, 100 * loss,
                100 * e.standard_error / background);
    EXPECT_GT(loss, -3.0 * e.standard_error / background) << segments;  // no light made
    EXPECT_LT(loss, segments == 12 ? 0.015 : 0.008) << segments;
  }
}

}  // namespace
}  // namespace bouguer
