// The transport core's seams: splits of a render give the same image bit for bit, the light
// tracer and the path tracer converge to the same image, adjoint BSDFs, light selection by power,
// camera importance.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>
#include <random>

#include "bouguer/core/frame.h"
#include "bouguer/io/image_io.h"
#include "bouguer/lights/light.h"
#include "bouguer/materials/surface_bsdf.h"
#include "bouguer/render/camera.h"
#include "bouguer/render/compare.h"
#include "bouguer/integrators/events.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/integrators/walk.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
using test::busy_scene;
using test::caustic_scene;
using test::room_scene;

constexpr double kPi = std::numbers::pi;


bool bit_identical(const Film& a, const Film& b) {
  return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// Next-event estimation's probability at a medium vertex (integrators/dense_media.h:
// nee_probability_in_medium), in a 10 mm ball of σ_s = 1000 per m: 1 within 3 mean free paths of
// the surface, exp(3 − τ_R) below, 1/64 from τ_R = 3 + ln 64 on; 1 near a point light and where
// the least-scattering wavelength sees the surface within reach; the single wavelength's σ_s in a
// walk of one wavelength. Reusing the last query (SurfaceDistance) gives the same probability as a fresh
// one along a walk of small steps where the bound decides; between, near the last query, the
// probability from its nearest point's plane (near_surface_m) is a fresh query's below a flat face,
// and close to it below the ball's curved one.
// A 10 mm ball of a scattering medium (σ_s over 400–700 nm, an optional density), one light.
RenderScene ball_of_medium(const char* sigma, const char* density, const char* lights, const char* shape = "") {
  return compile(parse_scene(fmt::format(R"({{
      "camera": {{"position": [0, 0, 0.1], "look_at": [0, 0, 0], "fov_deg": 5, "resolution": [4, 4]}},
      "media": {{"milky": {{"ior": 1.33, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                "value": [5, 20]}}, "scattering": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                "value": {}, "phase": {{"type": "henyey_greenstein", "g": 0.8}}{}}}}}}},
      "objects": [{{"name": "ball", "shape": {{"type": "sphere", "radius": "10 mm"{}}}, "inside": "milky"}}],
      "lights": [{}]
    }})", sigma, density, shape, lights), "nee.json"));
}

TEST(NeeProbability, FollowsTheDistanceToTheSurfacesAndTheLights) {
  auto scene_with = [](const char* sigma, const char* density, const char* lights) {
    return ball_of_medium(sigma, density, lights);
  };
  const RenderScene grey = scene_with("[1000, 1000]", "", R"({"type": "distant", "direction": [0, 0, -1], "spectrum": "D65"})");
  const SpectralTables<kHeroCount> tables(grey.spectra, SpectralMode::hero);
  const Camera camera(grey.camera);
  const SceneView<kHeroCount> v{grey, tables, camera, 8};
  const int milky = grey.surfaces[0].medium_behind;
  ASSERT_GE(milky, 0);
  const SampledWavelengths<kHeroCount> w = tables.wavelengths(0.3);
  auto q_at = [&](const SceneView<kHeroCount>& view, const Vec3& x, const SampledWavelengths<kHeroCount>& wl) {
    SurfaceDistance fresh;
    return nee_probability_in_medium(view, milky, x, wl, fresh);
  };
  EXPECT_DOUBLE_EQ(q_at(v, {0, 0, 0}, w), kNeeFloor);              // τ_R = 10
  EXPECT_DOUBLE_EQ(q_at(v, {0, 0.0075, 0}, w), 1.0);               // τ_R = 2.5
  EXPECT_NEAR(q_at(v, {0.006, 0, 0}, w), std::exp(3.0 - 4.0), 1e-7);  // τ_R = 4 (an analytic sphere: exact)
  // The same ball with a point light at its centre: every vertex near it connects.
  const RenderScene lamp = scene_with("[1000, 1000]", "", R"({"type": "point", "position": [0, 0, 0], "spectrum": "D65", "scale": 1})");
  const SceneView<kHeroCount> vl{lamp, tables, camera, 8};
  EXPECT_DOUBLE_EQ(q_at(vl, {0.001, 0, 0}, w), 1.0);
  EXPECT_NEAR(q_at(vl, {0.0055, 0, 0}, w), std::exp(3.0 - 4.5), 1e-7);  // 4.5 mm from both
  // Chromatic: σ_s 1000 → 100 per m, so the red end sees τ_R = 1 from the centre.
  const RenderScene chromatic = scene_with("[1000, 100]", "", R"({"type": "distant", "direction": [0, 0, -1], "spectrum": "D65"})");
  const SpectralTables<kHeroCount> ct(chromatic.spectra, SpectralMode::hero);
  const SceneView<kHeroCount> vc{chromatic, ct, camera, 8};
  SampledWavelengths<kHeroCount> wc = ct.wavelengths(0.3);
  EXPECT_DOUBLE_EQ(q_at(vc, {0, 0, 0}, wc), 1.0);
  // A walk of one wavelength at the blue end (σ_s ≈ 1000): deep again.
  std::size_t blue = 0;
  for (std::size_t k = 1; k < kHeroCount; ++k)
    if (wc.nm[k] < wc.nm[blue]) blue = k;
  wc.terminate_secondary(static_cast<int>(blue), wc.nm[blue]);
  ASSERT_LT(wc.nm[blue], 480.0);
  EXPECT_LT(q_at(vc, {0, 0, 0}, wc), 0.05);
  // A density that varies has no lower bound along a ray: always 1.
  const RenderScene varying = scene_with(
      "[1000, 1000]", R"(, "density": {"field": "exponential", "axis": [0, 1, 0], "value": 1, "scale_length": "10 mm"})",
      R"({"type": "distant", "direction": [0, 0, -1], "spectrum": "D65"})");
  const SceneView<kHeroCount> vv{varying, tables, camera, 8};
  EXPECT_DOUBLE_EQ(q_at(vv, {0, 0, 0}, w), 1.0);
  // Reuse: a walk of 2000 steps of 0.4 mm from the centre, clamped to the ball. Where the bound
  // decides (q = 1 or the floor), the same as a fresh query. Between, near the last query c, from
  // the plane through its nearest point: inside the ball that plane lies beyond the surface, its
  // distance R − x·ĉ against the surface's R − |x|, so q is at most the fresh one's and its
  // logarithm at most σ·(|x| − x·ĉ) below it (a plane on the wrong side, or a stale distance,
  // breaks one or the other). The same with the point lamp at the centre, whose distance |x| the
  // plane's estimate takes as a fresh query does.
  auto walk = [&](const SceneView<kHeroCount>& view, double radius_m, bool below_a_plane, const char* what) {
    SurfaceDistance reused;
    std::mt19937_64 rng(3);
    std::normal_distribution<double> step(0.0, 0.4e-3);
    Vec3 x{};
    int reused_bound = 0, planes = 0;
    for (int i = 0; i < 2000; ++i) {
      x = x + Vec3{step(rng), step(rng), step(rng)};
      if (length(x) > radius_m) x = x * (radius_m / length(x));
      const SurfaceDistance before = reused;
      const double q = nee_probability_in_medium(view, milky, x, w, reused), fresh = q_at(view, x, w);
      if (before.centre == reused.centre && before.radius_m == reused.radius_m) {
        const double moved = length(x - before.centre);
        if (before.radius_m + moved <= 0.003 || before.radius_m - moved >= (3.0 + std::log(64.0)) / 1000.0) {
          ++reused_bound;
          EXPECT_DOUBLE_EQ(q, fresh) << what << i;
        } else {
          planes += q > kNeeFloor && q < 1.0;
          // (1e-7: the plane's and the query's roundings, σ times about 1e-12 m)
          const double slack = (below_a_plane ? 0.0 : 1000.0 * (length(x) - dot(x, normalize(before.centre)))) + 1e-7;
          EXPECT_LE(std::log(q), std::log(fresh) + 1e-7) << what << i;
          EXPECT_GE(std::log(q), std::log(fresh) - slack) << what << i;
        }
      } else {
        EXPECT_DOUBLE_EQ(q, fresh) << what << i;
      }
    }
    std::printf("NEE probability (%s): of 2000 steps %d reused the bound, %d the plane (1/64 < q < 1)\n", what,
                reused_bound, planes);
    EXPECT_GT(reused_bound, 100) << what;
    EXPECT_GT(planes, 300) << what;
  };
  walk(v, 0.0095, false, "a ball");
  walk(vl, 0.0095, false, "a ball with a point lamp at its centre");
  // Below a flat face the plane is exact: the same walk in a slab 200 mm wide and 20 mm thick,
  // 5 mm below its top face (its bottom and sides always farther than the top).
  const RenderScene slab = compile(parse_scene(R"({
      "camera": {"position": [0, 0, 0.1], "look_at": [0, 0, 0], "fov_deg": 5, "resolution": [4, 4]},
      "media": {"milky": {"ior": 1.33, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                "value": [1000, 1000], "phase": {"type": "henyey_greenstein", "g": 0.8}}}},
      "objects": [{"name": "slab", "shape": {"type": "box", "size": ["200 mm", "200 mm", "20 mm"]},
                   "transform": [{"translate": [0, 0, "-5 mm"]}], "inside": "milky"}],
      "lights": [{"type": "distant", "direction": [0, 0, -1], "spectrum": "D65"}]
    })", "nee_slab.json"));
  const SpectralTables<kHeroCount> slab_tables(slab.spectra, SpectralMode::hero);
  const SceneView<kHeroCount> vb{slab, slab_tables, camera, 8};
  ASSERT_EQ(vb.scene.surfaces[0].medium_behind, milky);
  walk(vb, 0.0045, true, "below a flat face");
}

// The split's bins (integrators/dense_media.h: keep_split_wavelength, full mode). Walk i of a split
// draws its bin from the basis's split_probability at offset i/4 of split_u, so bin j is drawn on
// a set of split_u of measure P(j) for each i and must carry weight 1/(4·P(j)): then the walks'
// weighted throughputs average to the path's own in every bin, which is what keeps the split
// unbiased. Checked at points inside each bin's interval of split_u and at its two ends (the
// inverse of the table's running sum lands every one of them in the bin), with the weight against
// the interval's length; the kept bin alone carries throughput, every bin can be drawn, and the
// probabilities sum to 1. A weight from another density than the draw's (the eye-sensitivity
// density's mass, which the split used before) is 0.58 to 26 times off, bin by bin.
TEST(SplitWavelengths, EachBinIsDrawnAsOftenAsItsWeightAssumes) {
  const RenderScene scene =
      ball_of_medium("[1000, 100]", "", R"({"type": "distant", "direction": [0, 0, -1], "spectrum": "D65"})");
  const SpectralTables<kFullBins> tables(scene.spectra, SpectralMode::full);
  const Camera camera(scene.camera);
  const SceneView<kFullBins> v{scene, tables, camera, 8};
  const SpectralBasis<kFullBins>& basis = tables.basis();
  constexpr std::size_t kCount = kSplitCount<kFullBins>;
  double total = 0.0;
  for (std::size_t j = 0; j < kFullBins; ++j) {
    const double p = basis.split_probability[j], lo = j == 0 ? 0.0 : basis.split_cdf[j - 1];
    ASSERT_GT(p, 0.0) << "bin " << j << " can never be drawn";
    EXPECT_NEAR(basis.split_cdf[j] - lo, p, 1e-12) << "bin " << j;
    total += p;
    for (std::size_t i = 0; i < kCount; ++i)
      for (const double t : {1e-9, 0.25, 0.5, 0.75, 1.0 - 1e-9}) {
        SampledWavelengths<kFullBins> w = tables.wavelengths(0.5);
        w.split_u = lo + t * p - static_cast<double>(i) / kCount;
        if (w.split_u < 0.0) w.split_u += 1.0;
        SampledSpectrum<kFullBins> beta = SampledSpectrum<kFullBins>::constant(1.0f);
        const double weight = keep_split_wavelength(v, w, beta, i, 0.5);
        ASSERT_EQ(w.single, static_cast<int>(j)) << "walk " << i << " at " << t << " of bin " << j << "'s interval";
        EXPECT_NEAR(weight * kCount * p, 1.0, 1e-9) << "bin " << j;
        for (std::size_t k = 0; k < kFullBins; ++k)
          ASSERT_EQ(beta[k], k == j ? static_cast<float>(weight) : 0.0f) << "bin " << k << " of a walk keeping " << j;
      }
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_EQ(basis.split_cdf[kFullBins - 1], 1.0);
}

// The exit guide (integrators/events.h: ExitGuide) under a map that is bright in one patch and
// dim elsewhere, η = 1.33 across a plane: a direction drawn from it refracts at the plane into the
// map's own sample (Snell), and its reported density is the one it is drawn with: over its draws,
// the mean of 1/pdf is the solid angle of the directions that can leave through the plane, the
// cone θ < asin(1/η), 2π(1 − cos θc) (a density off by a constant factor, a Jacobian or a
// direction moves it). Directions into the medium and beyond the critical angle have density 0.
TEST(ExitGuide, DrawsTheDensityItReports) {
  const auto dir = test::scratch_dir("exit_guide");
  Film map(32, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      const float value = y < 4 && x > 9 && x < 15 ? 40.0f : (y < 8 ? 0.5f : 0.1f);
      map.set_rgb(x, y, Vec3f{value, value, value});
    }
  write_pfm(dir / "patch.pfm", map);
  const RenderScene scene = compile(parse_scene(fmt::format(R"({{
      "camera": {{"position": [0, 0, 0.1], "look_at": [0, 0, 0], "fov_deg": 5, "resolution": [4, 4]}},
      "objects": [], "background": {{"environment": "{}"}}
    }})", (dir / "patch.pfm").string()), "guide.json"));
  ASSERT_GE(scene.environment_light, 0);
  // A map this contrasted turns the guide on unless the scene says otherwise (kExitGuideContrast).
  std::printf("the patch map's contrast: %.2f\n", scene.environment->contrast);
  RenderSettings settings;
  EXPECT_TRUE(exit_guide_enabled(settings, scene));
  settings.exit_guide = false;
  EXPECT_FALSE(exit_guide_enabled(settings, scene));
  const double eta = 1.33;
  const ExitGuide guide{normalize(Vec3{0.3, 0.8, -0.2}), eta};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int draws = 200000;
  double sum = 0.0, sum2 = 0.0, worst_snell = 0.0;
  int drawn = 0;
  for (int i = 0; i < draws; ++i) {
    const double u1 = u(rng), u2 = u(rng);
    const auto wi = sample_exit_guide(scene, guide, u1, u2);
    if (!wi) continue;
    ++drawn;
    const double pdf = exit_guide_pdf(scene, guide, *wi);
    ASSERT_GT(pdf, 0.0);
    sum += 1.0 / pdf;
    sum2 += 1.0 / (pdf * pdf);
    // Snell at the plane: the tangential part grows by η, the direction stays in the plane of incidence.
    const auto li = sample_li(scene.lights[static_cast<std::size_t>(scene.environment_light)], Vec3{}, u1, u2);
    ASSERT_TRUE(li);
    const Vec3 t_in = *wi - guide.normal * dot(*wi, guide.normal), t_out = li->wi - guide.normal * dot(li->wi, guide.normal);
    worst_snell = std::max(worst_snell, length(t_in * eta - t_out));
  }
  const double mean = sum / draws, se = std::sqrt((sum2 / draws - mean * mean) / draws);
  const double cone = 2.0 * kPi * (1.0 - std::sqrt(1.0 - 1.0 / (eta * eta)));
  std::printf("exit guide: %d of %d drawn, mean 1/pdf %.4f ± %.4f, the cone %.4f; Snell within %.1e\n", drawn, draws,
              mean, se, cone, worst_snell);
  EXPECT_NEAR(mean, cone, 4.0 * se);
  EXPECT_LT(se, 0.01 * cone);
  EXPECT_LT(worst_snell, 1e-9);
  EXPECT_GT(drawn, draws / 10);
  EXPECT_EQ(exit_guide_pdf(scene, guide, -guide.normal), 0.0);
  const Frame frame(guide.normal);
  const double beyond = std::asin(1.0 / eta) + 0.05;
  EXPECT_EQ(exit_guide_pdf(scene, guide, frame.to_world({std::sin(beyond), 0.0, std::cos(beyond)})), 0.0);
  EXPECT_GT(exit_guide_pdf(scene, guide, frame.to_world({0.0, std::sin(beyond - 0.1), std::cos(beyond - 0.1)})), 0.0);
  EXPECT_EQ(exit_guide_pdf(scene, ExitGuide{}, guide.normal), 0.0);
}

// The scene's last scattering medium (−1: none).
int last_scattering_medium(const RenderScene& scene) {
  int found = -1;
  for (std::size_t m = 0; m < scene.media.size(); ++m)
    if (scattering_medium(scene, static_cast<int>(m))) found = static_cast<int>(m);
  return found;
}

// The connection through the interfaces stops where the walk would. From milk 0.8 mm inside a
// tumbler's side wall (milk | glass | air: two interfaces to the map), a connection allowed one
// more surface finds nothing in 2000 draws, and one allowed two finds the map through the wall.
// The guide there points out through the wall, with the milk's index over the air's.
TEST(ExitGuide, StopsWhereTheWalkWould) {
  const auto dir = test::scratch_dir("exit_guide_depth");
  Film white(16, 8);
  std::fill(white.rgb.begin(), white.rgb.end(), 1.0f);
  write_pfm(dir / "white.pfm", white);
  const RenderScene scene = compile(parse_scene(fmt::format(R"({{
      "camera": {{"position": [0, 0.05, 0.2], "look_at": [0, 0.05, 0], "fov_deg": 30, "resolution": [4, 4]}},
      "media": {{"glass": {{"ior": 1.52}},
                "milky": {{"ior": 1.35, "scattering": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                          "value": [1000, 1000], "phase": {{"type": "henyey_greenstein", "g": 0.8}}}}}}}},
      "objects": [{{"name": "tumbler", "shape": {{"type": "vessel", "wall": "2.5 mm", "fill": 0.8, "segments": 96,
                   "profile": [[0, 0], ["28 mm", 0], ["30 mm", "3 mm"], ["32 mm", "100 mm"]]}},
                   "inside": "glass", "contents": "milky"}}],
      "background": {{"environment": "{}"}}
    }})", (dir / "white.pfm").string()), "tumbler.json"));
  const int milky = last_scattering_medium(scene);
  ASSERT_GE(milky, 0);
  const SpectralTables<kHeroCount> tables(scene.spectra, SpectralMode::hero);
  const Camera camera(scene.camera);
  const SceneView<kHeroCount> v{scene, tables, camera, 8};
  SampledWavelengths<kHeroCount> w = tables.wavelengths(0.3);
  w.terminate_secondary(1, w.nm[1]);
  const Vec3 x{0.0275, 0.04, 0.0};
  SurfaceDistance near;
  const ExitGuide guide = exit_guide_at(v, milky, x, w, near, 0);
  ASSERT_TRUE(guide.active());
  EXPECT_GT(guide.normal.x, 0.99);
  EXPECT_NEAR(guide.eta, 1.35 / scene.media[static_cast<std::size_t>(scene.world_medium)].ior_reference, 1e-12);
  const PhaseFunction& phase = scattering_medium(scene, milky)->phase;
  std::uint64_t rays = 0;
  int found_one = 0, found_two = 0;
  for (int i = 0; i < 2000; ++i) {
    Rng a(1, static_cast<std::uint64_t>(i)), b(1, static_cast<std::uint64_t>(i));
    const Vec3 arrived = normalize(Vec3{1.0, 0.2, 0.1});
    if (!environment_through_interfaces(v, MediumPoint{x, arrived, phase, milky}, guide, w, a, rays, ThroughInterfaces{1, 0})
             .is_zero())
      ++found_one;
    if (!environment_through_interfaces(v, MediumPoint{x, arrived, phase, milky}, guide, w, b, rays, ThroughInterfaces{2, 0})
             .is_zero())
      ++found_two;
  }
  std::printf("exit guide through a tumbler's wall: %d of 2000 with one surface left, %d with two\n", found_one,
              found_two);
  EXPECT_EQ(found_one, 0);
  EXPECT_GT(found_two, 200);
}

// Where the nearest surface is an index-matched boundary, next-event estimation reaches the map
// from the vertex already: no guide there. A dense ball in vacuum under a contrasted map, a vertex
// 0.1 mm inside its surface: index 1.35, a guide out along the radius; index 1, none.
TEST(ExitGuide, NoneAtAnIndexMatchedBoundary) {
  const auto dir = test::scratch_dir("exit_guide_matched");
  Film map(32, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) map.set_rgb(x, y, Vec3f{y < 2 ? 50.0f : 0.2f, y < 2 ? 50.0f : 0.2f, y < 2 ? 50.0f : 0.2f});
  write_pfm(dir / "top.pfm", map);
  for (const double ior : {1.35, 1.0}) {
    const RenderScene scene = compile(parse_scene(fmt::format(R"({{
        "camera": {{"position": [0, 0, 0.1], "look_at": [0, 0, 0], "fov_deg": 5, "resolution": [4, 4]}},
        "world_medium": "vacuum",
        "media": {{"milky": {{"ior": {}, "scattering": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                            "value": [20000, 20000], "phase": {{"type": "henyey_greenstein", "g": 0.8}}}}}}}},
        "objects": [{{"name": "ball", "shape": {{"type": "sphere", "radius": "10 mm"}}, "inside": "milky"}}],
        "background": {{"environment": "{}"}}
      }})", ior, (dir / "top.pfm").string()), "ball.json"));
    const int milky = last_scattering_medium(scene);
    ASSERT_GE(milky, 0);
    RenderSettings settings;
    ASSERT_TRUE(exit_guide_enabled(settings, scene));
    const SpectralTables<kHeroCount> tables(scene.spectra, SpectralMode::hero);
    const Camera camera(scene.camera);
    const SceneView<kHeroCount> v{scene, tables, camera, 8};
    SampledWavelengths<kHeroCount> w = tables.wavelengths(0.3);
    w.terminate_secondary(1, w.nm[1]);
    SurfaceDistance near;
    const ExitGuide guide = exit_guide_at(v, milky, Vec3{0.0, 0.0099, 0.0}, w, near, 0);
    if (ior > 1.0) {
      ASSERT_TRUE(guide.active());
      EXPECT_GT(guide.normal.y, 0.999);
      EXPECT_NEAR(guide.eta, ior, 1e-12);
    } else {
      EXPECT_FALSE(guide.active());
    }
  }
}

// A ball_of_medium lit by a distant light, with full mode's tables and a view of it (which holds
// references to the others: not to be copied).
struct FullModeBall {
  RenderScene scene;
  SpectralTables<kFullBins> tables;
  Camera camera;
  SceneView<kFullBins> view;
  FullModeBall(const char* sigma, const char* shape, int max_depth)
      : scene(ball_of_medium(sigma, "", R"({"type": "distant", "direction": [0, 0, -1], "spectrum": "D65"})", shape)),
        tables(scene.spectra, SpectralMode::full),
        camera(scene.camera),
        view{scene, tables, camera, max_depth} {}
  FullModeBall(const FullModeBall&) = delete;
  FullModeBall& operator=(const FullModeBall&) = delete;
};

// A walk of one wavelength deep in a homogeneous medium takes its next collision without a ray
// when the distance bound allows (walk.h: walk_deep). For 2000 random points and directions in a
// 10 mm ball (analytic and tessellated) with absorption, at random wavelengths: whenever walk_deep
// takes a collision, the ray's way (intersect, then through_medium) finds the same point, the same
// throughput and ratios bit for bit, and leaves the random stream in the same state; and it takes
// most of them (a collision within a few mean free paths, the bound several of them).
TEST(WalkDeep, TakesTheCollisionTheRayWouldHaveGiven) {
  for (const char* shape : {"", R"(, "segments": 48)"}) {
    const FullModeBall ball("[2000, 800]", shape, 8);
    const RenderScene& scene = ball.scene;
    const SpectralTables<kFullBins>& tables = ball.tables;
    const SceneView<kFullBins>& v = ball.view;
    const int milky = scene.surfaces[0].medium_behind;
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int taken = 0, tried = 0;
    for (int i = 0; i < 2000; ++i) {
      Vec3 p{u(gen), u(gen), u(gen)}, d{u(gen), u(gen), u(gen)};
      if (length(p) > 1.0 || length(d) < 0.1) continue;
      p = p * 0.0095;
      d = normalize(d);
      SampledWavelengths<kFullBins> w = tables.wavelengths(0.0);
      const int bin = static_cast<int>((u(gen) + 1.0) * 0.5 * (kFullBins - 1));
      w.terminate_secondary(bin, w.nm[static_cast<std::size_t>(bin)]);
      WalkState<kFullBins> state;
      state.ray = {p, d};
      state.start = state.from = p;
      state.medium = milky;
      state.beta = SampledSpectrum<kFullBins>{};
      state.beta[static_cast<std::size_t>(bin)] = 1.5f;
      SurfaceDistance near;
      near.centre = p + Vec3{0.0003, 0, 0};
      near.radius_m = near.surface_m = scene.rays.distance_to_surfaces(near.centre, 1.0);
      Rng rng(7, static_cast<std::uint64_t>(i));
      ++tried;
      WalkState<kFullBins> deep = state;
      Rng deep_rng = rng;
      const auto x = walk_deep(v, deep, near, w, deep_rng);
      if (!x) {  // declined: nothing drawn, nothing changed
        Rng fresh = rng;
        EXPECT_EQ(deep_rng.next_u32(), fresh.next_u32()) << i;
        EXPECT_EQ(std::memcmp(deep.beta.v.data(), state.beta.v.data(), sizeof(float) * kFullBins), 0) << i;
        continue;
      }
      ++taken;
      WalkState<kFullBins> ray = state;
      Rng ray_rng = rng;
      const auto hit = scene.rays.intersect(ray.ray);
      ASSERT_TRUE(hit);
      const auto y = through_medium(v, ray.medium, ray.start, d, *hit, w, ray_rng, ray.beta, ray.mis);
      ASSERT_TRUE(y) << i;
      EXPECT_EQ(*x, *y) << i;
      EXPECT_EQ(std::memcmp(deep.beta.v.data(), ray.beta.v.data(), sizeof(float) * kFullBins), 0) << i;
      EXPECT_EQ(std::memcmp(deep.mis.r_l.v.data(), ray.mis.r_l.v.data(), sizeof(float) * kFullBins), 0) << i;
      EXPECT_EQ(deep_rng.next_u32(), ray_rng.next_u32()) << i;
    }
    std::printf("walk_deep (%s): %d of %d collisions taken without a ray\n", *shape ? "mesh" : "analytic", taken, tried);
    EXPECT_GT(taken, tried / 2);
  }
}

// The same through random_walk: walks of one wavelength from outside into a denser ball (σ_s
// 20000 → 8000 per m; refraction at n = 1.33, then hundreds of collisions), once with the bound that next-event estimation keeps
// (so walk_deep takes most collisions without a ray) and once with the bound thrown away after each
// vertex (every collision by a ray): the same vertices, the same throughputs bit for bit, the same
// random stream at the end.
template <std::size_t N>
struct RecordVertices {
  static constexpr bool kReverse = false;
  const SceneView<N>& v;
  const SampledWavelengths<N>& w;
  bool keep_bound;
  std::vector<Vec3> points;
  std::vector<float> betas;
  SurfaceDistance near;
  const SurfaceDistance& surface_distance() const { return near; }
  bool vertex(const Vertex<N>& x) {
    points.push_back(x.point);
    betas.push_back(x.beta[static_cast<std::size_t>(w.single)]);
    if (x.kind == VertexKind::medium) {
      nee_probability_in_medium(v, x.medium, x.point, w, near);
      if (!keep_bound) near = {};
    }
    return x.kind != VertexKind::light && points.size() < 20000;
  }
};

TEST(WalkDeep, RandomWalksAreTheSameWithAndWithoutIt) {
  for (const char* shape : {"", R"(, "segments": 48)"}) {
    const FullModeBall ball("[20000, 8000]", shape, 1000);
    const RenderScene& scene = ball.scene;
    const SpectralTables<kFullBins>& tables = ball.tables;
    const SceneView<kFullBins>& v = ball.view;
    std::size_t vertices = 0;
    std::array<std::uint64_t, 2> rays{};
    for (int i = 0; i < 40; ++i) {
      SampledWavelengths<kFullBins> w = tables.wavelengths(0.0);
      const int bin = (i * 37) % kFullBins;
      w.terminate_secondary(bin, w.nm[static_cast<std::size_t>(bin)]);
      std::array<RecordVertices<kFullBins>*, 2> runs{};
      std::array<Rng, 2> rngs{Rng(5, static_cast<std::uint64_t>(i)), Rng(5, static_cast<std::uint64_t>(i))};
      std::array<WalkState<kFullBins>, 2> states;
      std::vector<std::unique_ptr<RecordVertices<kFullBins>>> keep;
      for (int k = 0; k < 2; ++k) {
        WalkState<kFullBins>& state = states[static_cast<std::size_t>(k)];
        state.ray = {{0.001 * (i % 7 - 3), 0.0005 * (i % 5 - 2), 0.05}, {0, 0, -1}};
        state.start = state.from = state.ray.origin;
        state.medium = scene.world_medium;
        state.beta = SampledSpectrum<kFullBins>{};
        state.beta[static_cast<std::size_t>(bin)] = 1.0f;
        keep.push_back(std::make_unique<RecordVertices<kFullBins>>(RecordVertices<kFullBins>{v, w, k == 0, {}, {}, {}}));
        runs[static_cast<std::size_t>(k)] = keep.back().get();
        SampledWavelengths<kFullBins> wk = w;
        random_walk(v, WalkMedia{}, TransportMode::radiance, state, wk, rngs[static_cast<std::size_t>(k)],
                    rays[static_cast<std::size_t>(k)], *keep.back());
      }
      ASSERT_EQ(runs[0]->points.size(), runs[1]->points.size()) << i;
      EXPECT_TRUE(runs[0]->points == runs[1]->points) << i;
      EXPECT_TRUE(runs[0]->betas == runs[1]->betas) << i;
      EXPECT_EQ(rngs[0].next_u32(), rngs[1].next_u32()) << i;
      vertices += runs[0]->points.size();
    }
    std::printf("random walks with and without walk_deep (%s): %zu vertices, the same; %llu rays against %llu\n",
                *shape ? "mesh" : "analytic", vertices, static_cast<unsigned long long>(rays[0]),
                static_cast<unsigned long long>(rays[1]));
    EXPECT_GT(vertices, 40u * 100u);
    EXPECT_LT(rays[0] * 4, rays[1]);  // most collisions were taken without a ray
  }
}

TEST(Splits, SampleRangesAndPixelRegionsGiveTheWholeRenderBitForBit) {
  for (const char* integrator : {"whitted", "path", "light", "bdpt", "vcm"})
    for (const char* spectral : {"full", "hero", "rgb3"}) {
      const SceneDesc desc = parse_scene(busy_scene(integrator, spectral, 8), "busy.json");
      const RenderScene scene = compile(desc);
      const RenderSettings& settings = desc.render;
      RenderStats stats;
      RenderControl two_threads;
      two_threads.threads = 2;
      const Film whole = render(scene, settings, two_threads, stats);
      double sum = 0.0;
      for (float v : whole.rgb) sum += v;
      ASSERT_GT(sum, 0.0) << integrator << " " << spectral;

      FilmBuffer by_samples = make_film(scene, false);
      for (int s = 0; s < 8; s += 2)  // 4 sample ranges, one after another
        render_into(scene, settings, by_samples, PixelRegion::whole(scene.camera), {s, s + 2}, RenderControl{}, stats);
      EXPECT_TRUE(bit_identical(whole, resolve(by_samples, 8))) << integrator << " " << spectral << ": sample ranges";

      FilmBuffer by_regions = make_film(scene, false);
      const int w = scene.camera.width_px, h = scene.camera.height_px;
      for (const PixelRegion r : {PixelRegion{0, 0, 7, 5}, PixelRegion{7, 0, w, 5}, PixelRegion{0, 5, 11, h},
                                  PixelRegion{11, 5, w, h}})
        render_into(scene, settings, by_regions, r, {0, 8}, RenderControl{}, stats);
      EXPECT_TRUE(bit_identical(whole, resolve(by_regions, 8))) << integrator << " " << spectral << ": pixel regions";
    }
}


// A floor under a quad lamp 5 cm above it, the same scene at the origin and 10 m from it: the same
// image (the same samples, so within float rounding: measured 0.01 %). Shadow rays stop short of
// their target by 1e-4 of the way and by twice a ray's origin offset there; with the first alone,
// 10 m out the offset (4e-5 m) reached past the stop, the lamp blocked its own shadow rays and the
// floor came out 20 % dark (0.601 against 0.756).
TEST(Transmission, AFloorUnderACloseLampFarFromTheOriginIsLitAsAtTheOrigin) {
  auto floor = [](double x_m) {
    const Film f = test::render_text(fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [{0}, 0.03, 0], "look_at": [{0}, -1, 0], "up": [0, 0, -1],
                 "width": 0.1, "resolution": [8, 8]}},
      "render": {{"integrator": "path", "spectral": "rgb3", "spp": 64, "max_depth": 1, "seed": 1}},
      "world_medium": "vacuum",
      "objects": [
        {{"name": "floor", "shape": {{"type": "quad", "size": [1, 1]}},
          "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}, {{"translate": [{0}, 0, 0]}}],
          "material": {{"type": "diffuse", "reflectance": 0.8}}}},
        {{"name": "lamp", "shape": {{"type": "quad", "size": [0.4, 0.4]}},
          "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [{0}, 0.05, 0]}}],
          "emission": {{"spectrum": "D65", "scale": 1}}}}
      ],
      "background": {{"spectrum": "E", "scale": 0}}
    }})", x_m));
    return test::channel_estimate(f, 1, 0, 0, 8, 8).mean;
  };
  const double here = floor(0.0), far = floor(10.0);
  std::printf("floor under a lamp 5 cm above: at the origin %.5f, 10 m from it %.5f\n", here, far);
  EXPECT_NEAR(far / here, 1.0, 0.002);
}

TEST(LightTracer, ConvergesToThePathTracerInADiffuseRoom) {
  const Film path = test::render_text(room_scene("path", 4096, 1));
  const Film light = test::render_text(room_scene("light", 4096, 2));
  const ImageDifference d = compare_images(path, light);
  std::printf("diffuse room, light vs path at 4096 spp: mean ΔE00 %.3f, p95 %.3f\n", d.mean, d.p95);
  EXPECT_LT(d.mean, 0.5);
}


// The light tracer against the path tracer on a floor beside a red glass ball (a mesh) under a
// disk lamp, over the pixels that see the floor (at their corners and centre): around the ball
// (its shadow, which light through the glass tints; in the bounding box of the pixels that see the
// ball grown by 2 pixels) and the rest, each region's mean in each channel from 8 seeds of each
// estimator, within 4 standard errors of the difference, those under 2 % of the path tracer's
// mean: the splats' normalisation or the importance-mode BSDF wrong by a per cent would show, and
// the light through the glass into the shadow wrong by more than its share of the region allows
// (an error that moved light within a region, keeping its mean, would not). Measured: standard
// errors 0.05-0.2 % of the means, the light tracer 1.0005-1.0011 of the path tracer around the
// ball and 0.9993-0.9994 elsewhere. (It compared the two images by mean ΔE00 below 0.5, at 4096
// and 16 384 spp: 0.256, for 3.5 times the time.)
TEST(LightTracer, ConvergesToThePathTracerOnACausticFloor) {
  SceneDesc desc = parse_scene(caustic_scene("path", 128, 1), "caustic.json");
  const RenderScene scene = compile(desc);
  const Camera camera(scene.camera);
  constexpr int kSize = 16, kSeeds = 8;
  std::vector<int> region(kSize * kSize, -1);  // -1 not floor, 0 around the ball, 1 the rest
  int x0 = kSize, y0 = kSize, x1 = -1, y1 = -1;  // the pixels that see the ball
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      bool floor = true;
      for (const auto& [fx, fy] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, {1.0, 1.0}, {0.5, 0.5}}) {
        const auto hit = scene.rays.intersect(camera.generate_ray(x + fx, y + fy));
        const bool f = hit && scene.surfaces[hit->geometry].object == "floor";
        if (hit && scene.surfaces[hit->geometry].object == "ball")
          x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
        floor = floor && f;
      }
      if (floor) region[static_cast<std::size_t>(y * kSize + x)] = 1;
    }
  ASSERT_LE(x0, x1);
  int counts[2] = {0, 0};
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      int& r = region[static_cast<std::size_t>(y * kSize + x)];
      if (r == 1 && x >= x0 - 2 && x <= x1 + 2 && y >= y0 - 2 && y <= y1 + 2) r = 0;
      if (r >= 0) ++counts[r];
    }
  ASSERT_GT(counts[0], 20);
  ASSERT_GT(counts[1], 100);
  const std::vector<Film> path = test::render_seeds(desc, kSeeds, 1);
  desc.render.integrator = IntegratorType::light;
  desc.render.spp = 512;
  const std::vector<Film> light = test::render_seeds(desc, kSeeds, 1);
  auto estimate = [&](const std::vector<Film>& films, int r, int c) {
    std::vector<double> means;
    for (const Film& f : films) {
      double sum = 0.0;
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
          if (region[static_cast<std::size_t>(y * kSize + x)] == r) sum += f.rgb_at(x, y)[c];
      means.push_back(sum / counts[r]);
    }
    return test::mean_estimate(means);
  };
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) {
      const test::Estimate p = estimate(path, r, c), l = estimate(light, r, c);
      const double se = std::hypot(p.standard_error, l.standard_error);
      std::printf("caustic floor, %s (%d pixels), ch %d: path %.5f ± %.5f, light tracer %.5f ± %.5f (%.4f of it)\n",
                  r == 0 ? "around the ball" : "the rest", counts[r], c, p.mean, p.standard_error, l.mean,
                  l.standard_error, l.mean / p.mean);
      EXPECT_LT(std::abs(l.mean - p.mean), 4.0 * se) << "region " << r << " ch " << c;
      EXPECT_LT(4.0 * se, 0.02 * p.mean) << "region " << r << " ch " << c << ": too noisy";
    }
}

// For every BSDF, the importance-mode value is the radiance-mode value with wo and wi exchanged:
// f*(wo, wi) = f(wi, wo), where eval gives f·|cos θi|.
TEST(Bsdf, ImportanceModeIsTheAdjoint) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto direction = [&] {
    const double z = 2.0 * u(rng) - 1.0, r = std::sqrt(1.0 - z * z), phi = 2.0 * kPi * u(rng);
    return Vec3{r * std::cos(phi), r * std::sin(phi), z};
  };
  constexpr std::size_t N = 3;
  SampledSpectrum<N> reflectance, n, k;
  reflectance.v = {0.8f, 0.5f, 0.2f};
  n.v = {0.2f, 0.9f, 1.1f};
  k.v = {3.9f, 2.4f, 2.2f};
  const DielectricAlbedo albedo = DielectricAlbedo::compute(0.3, 1.0, 1.5);
  const DielectricAlbedo albedo_water = DielectricAlbedo::compute(0.15, 1.33, 1.7);
  const std::vector<Bsdf<N>> bsdfs = {
      DiffuseReflection<N>{reflectance},
      ConductorReflection<N>{n, k, 1.0, 0.25},
      RoughDielectric{{{0.3}, 1.0, 1.5, nullptr}},
      RoughDielectric{{{0.3}, 1.0, 1.5, &albedo}},
      RoughDielectric{{{0.15}, 1.33, 1.7, &albedo_water}},
  };
  int compared = 0, refractions = 0;
  for (std::size_t b = 0; b < bsdfs.size(); ++b)
    for (int i = 0; i < 4000; ++i) {
      const Vec3 wo = direction(), wi = direction();
      const SampledSpectrum<N> imp = eval(bsdfs[b], wo, wi, TransportMode::importance);
      const SampledSpectrum<N> rad_swapped = eval(bsdfs[b], wi, wo, TransportMode::radiance);
      for (std::size_t c = 0; c < N; ++c) {
        const double f_imp = imp[c] / std::abs(wi.z), f_swapped = rad_swapped[c] / std::abs(wo.z);
        ASSERT_NEAR(f_imp, f_swapped, 1e-5 * std::max(1.0, std::abs(f_swapped))) << "bsdf " << b << " sample " << i;
      }
      if (imp[0] > 0.0f) ++compared;
      if (imp[0] > 0.0f && wo.z * wi.z < 0.0) ++refractions;
    }
  EXPECT_GT(compared, 8000);
  EXPECT_GT(refractions, 1000);
  // The radiance mode itself is not symmetric across a refraction (radiance is n² larger in glass):
  // the test above would fail if either mode put the η² factor on the wrong side.
  const Bsdf<N> glass = RoughDielectric{{{0.3}, 1.0, 1.5, nullptr}};
  const Vec3 wo = normalize(Vec3{0.2, 0.1, 1.0}), wi = normalize(Vec3{-0.1, 0.05, -1.0});
  const double ratio = (eval(glass, wo, wi, TransportMode::radiance)[0] / std::abs(wi.z)) /
                       (eval(glass, wi, wo, TransportMode::radiance)[0] / std::abs(wo.z));
  EXPECT_NEAR(ratio, 1.0 / (1.5 * 1.5), 1e-6);

  // Delta lobes: a smooth interface refracts wo to wi and wi back to wo; radiance entering glass
  // from air is scaled by (1/1.5)² and leaving it by 1.5², importance (flux) by 1 both ways.
  const Bsdf<N> smooth = SmoothDielectric{1.0, 1.5};
  const Vec3 outside = normalize(Vec3{0.3, -0.2, 0.8});
  const auto in_rad = sample(smooth, outside, 0.999, 0.0, 0.0, TransportMode::radiance);
  const auto in_imp = sample(smooth, outside, 0.999, 0.0, 0.0, TransportMode::importance);
  ASSERT_TRUE(in_rad && in_imp && in_rad->transmitted && in_imp->transmitted);
  EXPECT_NEAR(in_rad->weight[0], 1.0 / (1.5 * 1.5), 1e-6);
  EXPECT_FLOAT_EQ(in_imp->weight[0], 1.0f);
  const auto back = sample(smooth, in_rad->wi, 0.999, 0.0, 0.0, TransportMode::radiance);
  ASSERT_TRUE(back && back->transmitted);
  EXPECT_NEAR(length(back->wi - outside), 0.0, 1e-9);
  EXPECT_NEAR(back->weight[0], 1.5 * 1.5, 1e-5);
  const auto back_imp = sample(smooth, in_rad->wi, 0.999, 0.0, 0.0, TransportMode::importance);
  ASSERT_TRUE(back_imp && back_imp->transmitted);
  EXPECT_FLOAT_EQ(back_imp->weight[0], 1.0f);
}

// A large dim panel and a small bright one (each giving the floor about half its light), over a
// diffuse floor seen from above: next-event estimation by power keeps the mean and lowers the
// variance against the former choice by area.
TEST(LightSelection, ByPowerKeepsTheMeanAndLowersTheVariance) {
  const std::string json = R"({
    "camera": {"type": "orthographic", "position": [0, 0.3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
               "width": 1.6, "resolution": [8, 8]},
    "render": {"integrator": "path", "spectral": "rgb3", "spp": 4, "max_depth": 1},
    "objects": [
      {"name": "floor", "shape": {"type": "quad", "size": [2, 2]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
       "material": {"type": "diffuse", "reflectance": 0.5}},
      {"name": "dim", "shape": {"type": "quad", "size": [4, 4]},
       "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 1.0, 0]}],
       "emission": {"spectrum": "D65", "scale": 0.5}},
      {"name": "bright", "shape": {"type": "quad", "size": [0.05, 0.05]},
       "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.5, 0]}],
       "emission": {"spectrum": "D65", "scale": 600}}
    ]
  })";
  SceneDesc desc = parse_scene(json, "lights.json");
  const RenderScene by_power = compile(desc);
  RenderScene by_area = compile(desc);
  std::vector<double> area;
  std::vector<bool> is_area;
  for (const Light& l : by_area.lights) {
    const auto* a = std::get_if<AreaLight>(&l);
    area.push_back(a ? a->area_m2 : 0.0);
    is_area.push_back(a != nullptr);
  }
  by_area.area_lights = LightDistribution::by_power(area, is_area);  // the former choice: by area
  constexpr int kRuns = 400;
  auto stats = [&](const RenderScene& scene, double& mean, double& variance) {
    std::vector<double> sum(64, 0.0), sum2(64, 0.0);
    for (int r = 0; r < kRuns; ++r) {
      RenderSettings settings = desc.render;
      settings.seed = static_cast<std::uint64_t>(r);
      RenderStats st;
      const Film f = render(scene, settings, RenderControl{}, st);
      for (int p = 0; p < 64; ++p) {
        const double g = f.rgb[static_cast<std::size_t>(3 * p + 1)];
        sum[static_cast<std::size_t>(p)] += g, sum2[static_cast<std::size_t>(p)] += g * g;
      }
    }
    mean = variance = 0.0;
    for (int p = 0; p < 64; ++p) {
      const double m = sum[static_cast<std::size_t>(p)] / kRuns;
      mean += m / 64.0;
      variance += (sum2[static_cast<std::size_t>(p)] / kRuns - m * m) / 64.0;
    }
  };
  double mean_power = 0, var_power = 0, mean_area = 0, var_area = 0;
  stats(by_power, mean_power, var_power);
  stats(by_area, mean_area, var_area);
  std::printf("light selection: by area mean %.4f variance %.3g; by power mean %.4f variance %.3g\n", mean_area,
              var_area, mean_power, var_power);
  // The means agree within 4 standard errors of their difference (64 pixels × kRuns renders).
  const double se = std::sqrt((var_power + var_area) / (64.0 * kRuns));
  EXPECT_NEAR(mean_power, mean_area, 4.0 * se);
  EXPECT_LT(var_power, 0.5 * var_area);
}

// Camera importance integrates to one over the film, and a point lands where its ray started.
TEST(Camera, ImportanceIsNormalisedAndFilmPositionsRoundTrip) {
  for (const CameraType type : {CameraType::pinhole, CameraType::orthographic}) {
    CameraDesc d;
    d.type = type;
    d.position_m = {0.1, 0.2, 1.0};
    d.look_at_m = {0, 0, 0};
    d.width_px = 64;
    d.height_px = 48;
    d.fov_deg = 50.0;
    d.width_m = 0.4;
    const Camera camera(d);
    double integral = 0.0;
    constexpr int kSteps = 200;
    for (int j = 0; j < kSteps; ++j)
      for (int i = 0; i < kSteps; ++i) {
        const double fx = (i + 0.5) * 64.0 / kSteps, fy = (j + 0.5) * 48.0 / kSteps;
        const Ray r = camera.generate_ray(fx, fy);
        const auto [pdf_pos, pdf_dir] = camera.pdf_we(r);
        // Uniform film positions: We·cos θ / (pdf_pos · pdf_dir) averages to 1 over the film.
        integral += camera.we(r) * dot(r.direction, camera.forward) / (pdf_pos * pdf_dir) / (kSteps * kSteps);
        const Vec3 p = r.origin + r.direction * 0.7;
        const auto at = camera.film_position(p);
        ASSERT_TRUE(at);
        EXPECT_NEAR((*at)[0], fx, 1e-9);
        EXPECT_NEAR((*at)[1], fy, 1e-9);
      }
    EXPECT_NEAR(integral, 1.0, 1e-9) << static_cast<int>(type);
  }
}

}  // namespace
}  // namespace bouguer

namespace bouguer {
namespace {

// One table of integrators and spectral modes: the loader accepts every name in it, the command
// line offers each with its summary, and the documentation lists them all.
TEST(IntegratorTable, TheLoaderTheCommandLineAndTheDocsUseIt) {
  const std::string help = test::run_bouguer({"render", "--help"}).out;
  const std::string rendering = test::read_file(std::filesystem::path(BOUGUER_SOURCE_DIR) / "docs" / "rendering.md");
  const std::string format = test::read_file(std::filesystem::path(BOUGUER_SOURCE_DIR) / "docs" / "scene-format.md");
  std::string integrators, modes;
  for (const IntegratorInfo& i : integrator_table()) {
    if (!integrators.empty()) integrators += '|';
    integrators.append(i.name);
    const SceneDesc d = parse_scene(
        fmt::format(R"({{"render": {{"integrator": "{}"}}, "objects": [{{"shape": {{"type": "quad", "size": [1, 1]}},
                    "material": {{"type": "diffuse"}}}}]}})",
                    i.name),
        "table.json");
    EXPECT_EQ(d.render.integrator, i.type);
    EXPECT_NE(help.find(std::string(i.summary)), std::string::npos) << i.name;
    EXPECT_NE(format.find(fmt::format("`\"{}\"`", i.name)), std::string::npos) << i.name;
  }
  for (const SpectralModeInfo& m : spectral_mode_table()) {
    if (!modes.empty()) modes += '|';
    modes.append(m.name);
    EXPECT_NE(help.find(std::string(m.summary)), std::string::npos) << m.name;
  }
  EXPECT_NE(rendering.find("[--integrator " + integrators + "]"), std::string::npos) << integrators;
  EXPECT_NE(rendering.find("[--spectral " + modes + "]"), std::string::npos) << modes;
  EXPECT_EQ(integrator_names(), "whitted, path, light, bdpt, vcm or auto");
}

}  // namespace
}  // namespace bouguer
