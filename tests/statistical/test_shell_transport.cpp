// Shell transport (#37: media/shell_walks.h, integrators/shell_hops.h): the tables against two
// exact martingales of the walk, then the path tracer with and without it on a ball lit from one
// side, then bit for bit over threads and sample ranges.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <numbers>
#include <vector>

#include "bouguer/core/rng.h"
#include "bouguer/media/shell_walks.h"
#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/shell_hops.h"
#include "bouguer/integrators/walk.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/render/render.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

TEST(ShellWalks, AClassIsTheLargestSphereThatFits) {
  EXPECT_EQ(shell_class(kShellSmallestRadius * 0.999), -1);
  EXPECT_EQ(shell_class(kShellSmallestRadius), 0);
  EXPECT_EQ(shell_class(kShellSmallestRadius * kShellRatio * 0.999), 0);
  EXPECT_EQ(shell_class(kShellSmallestRadius * kShellRatio * 1.001), 1);
  EXPECT_EQ(shell_class(1e12), kShellClasses - 1);
  EXPECT_EQ(shell_class(std::nan("")), -1);
  for (int k = 0; k < kShellClasses; ++k) EXPECT_EQ(shell_class(shell_radius(k)), k);
}

// Every exit is on its sphere, flying outwards, after at least the radius; a table is the same
// for the same stream and another for another.
TEST(ShellWalks, EveryExitLiesOnItsSphereAndATableRepeatsForItsStream) {
  const PhaseFunction phase = HenyeyGreensteinPhase{0.85};
  const ShellTable a = make_shell_table(phase, 7, 3), b = make_shell_table(phase, 7, 3), c = make_shell_table(phase, 7, 4);
  ASSERT_EQ(a.exits.size(), static_cast<std::size_t>(kShellClasses * kShellEntries));
  int differ = 0;
  for (int k = 0; k < kShellClasses; ++k)
    for (int i = 0; i < kShellEntries; ++i) {
      const ShellExit& e = a.at(k, i);
      const Vec3 p{e.position[0], e.position[1], e.position[2]}, d{e.direction[0], e.direction[1], e.direction[2]};
      EXPECT_NEAR(length(p), 1.0, 1e-6);
      EXPECT_NEAR(length(d), 1.0, 1e-6);
      EXPECT_GT(dot(p, d), 0.0) << "an exit flies inwards";
      EXPECT_GE(e.length, shell_radius(k) * (1.0 - 1e-6));
      EXPECT_GE(e.collisions, 0);
      EXPECT_LE(e.collisions, kMaxShellCollisions + 1);  // (+1: a walk cut short)
      EXPECT_EQ(std::memcmp(&e, &b.at(k, i), sizeof(ShellExit)), 0);
      differ += e.length != c.at(k, i).length;
    }
  EXPECT_GT(differ, kShellClasses * kShellEntries / 2);
}

// A walk's kept collision (for the lamps only connections reach: integrators/shell_hops.h) is one
// of its collisions, each with probability 1/n, and keeping it leaves the walk as it was. One walk
// (the same stream each time) kept by 20 000 pick streams: its exit the same each time, every one
// of its n collisions kept, the counts uniform by a χ² test (at 6 standard deviations of its n − 1
// degrees of freedom), and consecutive kept points a flight apart along the direction the later
// one arrived along. What it catches: a reservoir that favours early or late collisions (the
// c-th, after the first, kept with probability 1/(c + 1): χ² 632 and 559 for limits of 82 and
// 89, measured on purpose), a
// direction that is the one leaving the collision, points or lengths in other units, and keeping
// that changes the walk's own numbers (the exits would differ with and without it).
TEST(ShellWalks, AKeptCollisionIsUniformOverTheWalksCollisions) {
  for (const double g : {0.0, 0.85}) {
    const PhaseFunction phase = g == 0.0 ? PhaseFunction{IsotropicPhase{}} : PhaseFunction{HenyeyGreensteinPhase{g}};
    const double tau = shell_radius(0);
    // A walk of 20 to 80 collisions from this stream (a χ² with enough cells, each well filled).
    Rng start(5, 0);
    ShellExit walk;
    for (;;) {
      const Rng before = start;
      walk = walk_out_of_sphere(tau, phase, start);
      if (walk.collisions >= 20 && walk.collisions <= 80) {
        start = before;
        break;
      }
    }
    constexpr int kPicks = 20000;
    std::map<float, std::pair<int, ShellCollision>> by_length;  // (lengths differ between collisions)
    for (int i = 0; i < kPicks; ++i) {
      // (Streams far apart: PCG's streams of one seed that differ only in their increment start
      // correlated.)
      const auto u = static_cast<std::uint64_t>(i) + 1;
      Rng rng = start, pick(u * 0x9e3779b97f4a7c15ULL, u * 0xd1b54a32d192ed03ULL);
      ShellCollision kept;
      kept.length = -1.0f;
      const ShellExit e = walk_out_of_sphere(tau, phase, rng, &kept, &pick);
      ASSERT_EQ(std::memcmp(&e, &walk, sizeof(ShellExit)), 0) << "keeping a collision changed the walk";
      ASSERT_GT(kept.length, 0.0f) << "no collision kept";
      auto& [count, c] = by_length[kept.length];
      ++count;
      c = kept;
    }
    const int n = walk.collisions;
    ASSERT_EQ(static_cast<int>(by_length.size()), n) << "not every collision was kept";
    double chi2 = 0.0;
    const double expected = double(kPicks) / n;
    for (const auto& [l, entry] : by_length) chi2 += (entry.first - expected) * (entry.first - expected) / expected;
    std::printf("g %.2f: a walk of %d collisions, kept 20 000 times: chi-square %.1f on %d degrees of freedom\n", g, n,
                chi2, n - 1);
    EXPECT_LT(chi2, (n - 1) + 6.0 * std::sqrt(2.0 * (n - 1)));
    // Consecutive collisions: the later at the earlier plus its flight along its arriving direction.
    const ShellCollision* before = nullptr;
    for (const auto& [l, entry] : by_length) {
      const ShellCollision& c = entry.second;
      const Vec3 p{c.position[0], c.position[1], c.position[2]}, d{c.direction[0], c.direction[1], c.direction[2]};
      EXPECT_LT(length(p), 1.0);
      EXPECT_NEAR(length(d), 1.0, 1e-6);
      EXPECT_LT(c.length, walk.length);
      const Vec3 from = before ? Vec3{before->position[0], before->position[1], before->position[2]} : Vec3{};
      const double flight = (c.length - (before ? before->length : 0.0f)) / tau;
      const Vec3 gap = p - (from + d * flight);
      EXPECT_LT(length(gap), 1e-5 * (1.0 + c.length / tau)) << "collision at length " << c.length;
      before = &c;
    }
  }
  // A table keeps collisions beside the same exits.
  const PhaseFunction phase = HenyeyGreensteinPhase{0.85};
  const ShellTable plain = make_shell_table(phase, 7, 3, 4), keeping = make_shell_table(phase, 7, 3, 4, true);
  ASSERT_EQ(keeping.kept.size(), keeping.exits.size());
  EXPECT_TRUE(plain.kept.empty());
  EXPECT_EQ(std::memcmp(plain.exits.data(), keeping.exits.data(), plain.exits.size() * sizeof(ShellExit)), 0);
}

// Two martingales of a walk with unit flights and a phase function of mean cosine g, started at
// the origin flying along +z, whose outcomes at the exit the table stores. With X its position, D
// its direction and t the length travelled, the generator of the walk (drift D, a turn at rate 1
// to a direction of mean g·D) gives
//   X + D/(1 − g)                          (drift D, turns −D): E[τ·p + d/(1 − g)] = ẑ/(1 − g);
//   |X|² + 2·X·D/(1 − g) − 2·t/(1 − g)     (drift 2·X·D + 2/(1 − g), turns −2·X·D):
//                                          E[l] = (1 − g)·τ²/2 + τ·E[p·d],
// both exact at the exit (p, d: the exit's point on the unit sphere and direction, l its length;
// optional stopping holds, the exit time having exponential tails). What they catch: lengths that are not the walk's (a flight cut short
// or left out), exits in another frame (not flying along +z at the start), a phase function of
// another g (sample_phase's convention reversed: g → −g) or a sampler that is not exact.
TEST(ShellWalks, ExitsKeepTheWalksMartingales) {
  for (const double g : {0.0, 0.85}) {
    const PhaseFunction phase = g == 0.0 ? PhaseFunction{IsotropicPhase{}} : PhaseFunction{HenyeyGreensteinPhase{g}};
    constexpr int kWalks = 20000;
    for (const int k : {0, 2}) {
      const double tau = shell_radius(k);
      Rng rng(11, static_cast<std::uint64_t>(k));
      std::vector<double> ls, zs;
      for (int i = 0; i < kWalks; ++i) {
        const ShellExit e = walk_out_of_sphere(tau, phase, rng);
        const double pd = double(e.position[0]) * e.direction[0] + double(e.position[1]) * e.direction[1] +
                          double(e.position[2]) * e.direction[2];
        ls.push_back(double(e.length) - tau * pd);
        zs.push_back(tau * e.position[2] + e.direction[2] / (1.0 - g));
      }
      const auto [l, l_se] = test::mean_estimate(ls);
      const auto [z, z_se] = test::mean_estimate(zs);
      const double l_expected = (1.0 - g) * tau * tau / 2.0, z_expected = 1.0 / (1.0 - g);
      std::printf("g %.2f, tau %.0f: E[l - tau p.d] %.3f +- %.3f (exact %.3f); E[tau p_z + d_z/(1-g)] %.3f +- %.3f "
                  "(exact %.3f)\n",
                  g, tau, l, l_se, l_expected, z, z_se, z_expected);
      EXPECT_NEAR(l, l_expected, 4.0 * l_se) << "g " << g << " tau " << tau;
      EXPECT_NEAR(z, z_expected, 4.0 * z_se) << "g " << g << " tau " << tau;
      // (Resolution: lengths 3 % off, and a walk started along any other axis, which gives 0 or
      // −1/(1 − g) for the second, are seen.)
      EXPECT_LT(4.0 * l_se, 0.03 * l_expected);
      EXPECT_LT(4.0 * z_se, z_expected);
    }
  }
}

// A white furnace where spheres are taken: a strongly chromatic ball that does not absorb (σ_s
// 60 000 to 20 000 per m, g = 0.85, 3 mm: 60 to 180 mean free paths) of index 1 under a uniform
// sky, in hero mode, where the split keeps all four wavelengths at weight 1. Every walk of one
// wavelength leaves the ball at last with a throughput of exactly 1, spheres or not, and sees the
// sky: the image is the sky's to float rounding. What it catches: a sphere that changes the
// throughput (absorption where there is none, a weight) or ends a walk that should go on. Not where
// the walks leave (a uniform sky is the same everywhere): the lit ball below checks that.
TEST(ShellTransport, AWhiteFurnaceStaysWhite) {
  SceneDesc desc = parse_scene(test::ball_furnace(0.05, "[60000, 20000]", 0.85, "3 mm", 1.0), "furnace.json");
  desc.render.spectral = SpectralMode::hero;
  desc.render.spp = 16;
  desc.render.seed = 1;
  ASSERT_FALSE(ShellSet(compile(desc), desc.render.seed).empty()) << "the ball takes no spheres";
  const Film ball = test::render_desc(desc);
  desc.objects.clear();
  const Film sky = test::render_desc(desc);
  const double worst = test::largest_relative_difference(ball, sky);
  std::printf("white furnace with spheres, hero, 16 spp: largest relative difference from the sky %.2e\n", worst);
  // (Every throughput stays 1.0f exactly: nothing multiplies it but 1. A sphere that took 10⁻⁴ off
  // it, measured on purpose, left the image 7 % from the sky: the roulette then ends walks.)
  EXPECT_LT(worst, 1e-6);
}

// A ball of whole milk (the library's, g = 0.864, 3 mm: 60–210 mean free paths) under a sky
// brighter above than below, rendered with and without shell transport (hero mode, whose split
// into four walks of one wavelength is where spheres are taken): the image's mean per channel and
// the difference between its upper and lower halves agree within 4 standard errors, each measured
// from the spread of independent renders (a table serves every pixel of its sample, so the
// pixels of one render are not independent). What it catches, each measured on purpose (before
// the roulette between spheres; the scene and the tolerance the same): exits not
// turned to the flight's frame (green 6.2 and blue 12.5 standard errors brighter, the halves'
// difference 2.7–4.1 larger), absorption over the sphere's radius instead of the walk's length
// (green 8.4 and blue 10.5 standard errors brighter).
// (index_matched: the milk of index 1, so that the sky's shadow rays go through its surface.)
SceneDesc lit_milk_ball(bool shells, const char* radius = "3 mm", bool index_matched = false) {
  SceneDesc desc = parse_scene(fmt::format(R"({{
    "camera": {{"position": [0, "3 mm", "40 mm"], "look_at": [0, 0, 0], "fov_deg": 10, "resolution": [8, 8]}},
    "render": {{"integrator": "path", "spectral": "hero", "spp": 96, "max_depth": 64, "shell_transport": {}}},
    "world_medium": "vacuum",
    "media": {{"milk": {{{}"scattering": {{"library": "whole_milk"}}}}}},
    "objects": [{{"name": "ball", "shape": {{"type": "sphere", "radius": "{}"}}, "inside": "milk"}}],
    "background": {{"environment": "{}"}}
  }})", shells, index_matched ? R"("ior": 1, )" : "", radius, test::test_data("whole_milk_ball/sky.pfm").string()),
      "lit_milk_ball.json");
  return desc;
}

// Per render: the mean of each channel, then the upper half's mean less the lower half's.
std::array<double, 6> ball_figures(const Film& f) {
  std::array<double, 6> q{};
  const int h = f.height / 2;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double v = f.rgb_at(x, y)[c];
        q[static_cast<std::size_t>(c)] += v / (f.width * f.height);
        q[static_cast<std::size_t>(3 + c)] += (y < h ? v : -v) / (f.width * h);
      }
  return q;
}

TEST(ShellTransport, AgreesWithTheAnalogWalkOnABallLitFromAbove) {
  constexpr int kRenders = 6;
  std::array<std::array<test::Estimate, 6>, 2> e{};  // [shells][figure]
  for (const bool shells : {false, true}) {
    const std::vector<Film> films = test::render_seeds(lit_milk_ball(shells), kRenders, shells ? 101 : 1, 2);
    for (std::size_t i = 0; i < 6; ++i) {
      std::vector<double> per_render;
      for (const Film& f : films) per_render.push_back(ball_figures(f)[i]);
      e[shells][i] = test::mean_estimate(per_render);
    }
  }
  const char* what[6] = {"R", "G", "B", "R above - below", "G above - below", "B above - below"};
  for (std::size_t i = 0; i < 6; ++i) {
    const test::Estimate &analog = e[0][i], &shells = e[1][i];
    const double se_gap = std::hypot(analog.standard_error, shells.standard_error);
    std::printf("%s: analog %.4f, shells %.4f, gap %.4f = %.2f standard errors\n", what[i], analog.mean, shells.mean,
                shells.mean - analog.mean, (shells.mean - analog.mean) / se_gap);
    EXPECT_NEAR(shells.mean, analog.mean, 4.0 * se_gap) << what[i];
    // (Resolution: 3 % of a channel's mean, 15 % of the halves' difference.)
    EXPECT_LT(4.0 * se_gap, (i < 3 ? 0.03 : 0.15) * analog.mean) << what[i] << ": too few samples for the resolution";
  }
}

// The ball under the same sky and a point lamp beside it, above the camera, whose light only
// connections bring (through the ball's refracting surface, an exact sphere: manifold.h's
// casters), the spheres' kept collisions among them (integrators/shell_hops.h).
SceneDesc lamp_lit_milk_ball(bool shells) {
  SceneDesc desc = lit_milk_ball(shells);
  desc.render.spp = 4;
  DeltaLightDesc lamp;
  lamp.type = DeltaLightType::point;
  lamp.position_m = {0.004, 0.006, 0.004};
  lamp.intensity = ConstantSpectrum{2e-4};
  desc.lights.push_back(lamp);
  return desc;
}

// hop_shell's kept collision in the world (integrators/shell_hops.h), from the centre of the
// lamp-lit ball: turned and scaled as the exit is, so every product of the kept point and
// direction with the flight and with the exit, and the kept point's distance from the centre, are
// the table's own (the table's entry found from the random numbers the hop draws); its throughput
// is the absorption over its own length; and its connections to the lamp alone
// (delta_lights_in_medium) get through the ball's refracting surface (from those not so deep that
// the milk's transmittance rounds to 0 in a float), where in a ball of index 1 without the lamp
// they are nothing though the sky lights the same points. What it catches: a kept collision not
// turned (or turned otherwise than the exit), not scaled to the sphere, with the direction it
// left along, its throughput over the whole walk, connections that never reach the lamp or that
// reach the sky too (each measured on purpose: a kept point not turned, or a throughput over the
// whole walk, 200 hops of 200 off; connections to the sky too, 41 of 200 not nothing). The image
// tests cannot see these: the kept connections carry about 1 % of the lamp's light at most
// (docs/rendering.md).
TEST(ShellTransport, AKeptCollisionIsTheTablesTurnedAsTheExit) {
  const SceneDesc desc = lamp_lit_milk_ball(true);
  const RenderScene scene = compile(desc);
  const SpectralTables<kHeroCount> tables(scene.spectra, SpectralMode::hero);
  const Camera camera(scene.camera);
  const SceneView<kHeroCount> v{scene, tables, camera, desc.render.max_depth};
  ShellSet set(scene, 1);
  set.make({0, 1}, 1);
  const int milk = scene.surfaces[0].medium_behind;
  const ShellTable* table = set.table(0, milk);
  ASSERT_TRUE(table != nullptr && !table->kept.empty());
  const int nested = scene.surfaces[0].nested;
  const InsideSet inside = nested >= 0 ? nested_bit(nested) : 0;
  SampledWavelengths<kHeroCount> w = tables.wavelengths(0.3);
  w.terminate_secondary(0, w.nm[0]);
  SurfaceDistance bound;
  const double sigma_per_m = walk_sigma_min_per_m(v, milk, w, bound);
  const PhaseFunction& phase = scattering_medium(scene, milk)->phase;
  // The same ball of index 1 without its lamp: the connections to lamps alone find nothing.
  const SceneDesc unlit = lit_milk_ball(true, "3 mm", true);
  const RenderScene sky_only = compile(unlit);
  ASSERT_EQ(sky_only.surfaces[0].medium_behind, milk);
  ASSERT_EQ(sky_only.surfaces[0].nested, nested);
  const SceneView<kHeroCount> vs{sky_only, tables, camera, desc.render.max_depth};
  int connected = 0, sky_lit = 0;
  constexpr int kHops = 200;
  for (int i = 0; i < kHops; ++i) {
    Rng rng(77, static_cast<std::uint64_t>(i)), drawn = rng;
    const double u = rng.next_double(), z = 1.0 - 2.0 * rng.next_double(), r = std::sqrt(1.0 - z * z);
    const Vec3 d{r * std::cos(2.0 * std::numbers::pi * u), r * std::sin(2.0 * std::numbers::pi * u), z};
    drawn = rng;
    WalkState<kHeroCount> state;
    state.start = Vec3{};
    state.ray = Ray{state.start, d};
    state.medium = milk;
    state.inside = inside;
    state.beta[0] = 1.0f;
    ShellUse use;
    SurfaceDistance near;
    const auto hop = hop_shell(v, table, state, use, near, w, rng);
    ASSERT_TRUE(hop.has_value()) << i;
    // The entry: the first of a walk's, drawn first; its class from the sphere's radius.
    const int entry = static_cast<int>(drawn.next_u32() % kShellEntries);
    const double radius_m = length(hop->exit - hop->centre);
    const int k = static_cast<int>(std::lround(std::log(radius_m * sigma_per_m / kShellSmallestRadius) / std::log(kShellRatio)));
    ASSERT_NEAR(radius_m * sigma_per_m, shell_radius(k), 1e-6 * shell_radius(k)) << i;
    const ShellExit& e = table->at(k, entry);
    const ShellCollision& c = table->kept_at(k, entry);
    if (e.collisions == 0) continue;
    ASSERT_TRUE(hop->kept) << i;
    auto v3 = [](const std::array<float, 3>& a) { return Vec3{a[0], a[1], a[2]}; };
    const Vec3 exit_at = (hop->exit - hop->centre) / radius_m, kept_at = (hop->kept_point - hop->centre) / radius_m;
    const Vec3 exit_d = state.ray.direction;
    // (The entry is the one the hop took: its exit's own products first.)
    ASSERT_NEAR(dot(exit_at, d), e.position[2], 1e-5) << i;
    ASSERT_NEAR(dot(exit_d, d), e.direction[2], 1e-5) << i;
    EXPECT_NEAR(length(kept_at), length(v3(c.position)), 1e-5) << i;
    EXPECT_NEAR(dot(kept_at, d), c.position[2], 1e-5) << i;
    EXPECT_NEAR(dot(hop->kept_direction, d), c.direction[2], 1e-5) << i;
    EXPECT_NEAR(dot(kept_at, exit_at), dot(v3(c.position), v3(e.position)), 1e-5) << i;
    EXPECT_NEAR(dot(hop->kept_direction, exit_d), dot(v3(c.direction), v3(e.direction)), 1e-5) << i;
    EXPECT_GE(hop->kept_ordinal, 1);
    EXPECT_LE(hop->kept_ordinal, e.collisions);
    // Absorption over the kept length: ln β_kept / ln β_exit = l_kept / l.
    if (state.beta[0] < 1.0f)
      EXPECT_NEAR(std::log(hop->kept_beta) / std::log(state.beta[0]), c.length / e.length, 1e-3) << i;
    else
      EXPECT_EQ(hop->kept_beta, 1.0f) << i;
    const MediumPoint at{hop->kept_point, hop->kept_direction, phase, milk, inside};
    std::uint64_t rays = 0;
    const SampledSpectrum<kHeroCount> lamp = delta_lights_in_medium(v, at, w, state.mis.r_u, rng, rays, true);
    connected += lamp[0] > 0.0f;
    EXPECT_EQ(delta_lights_in_medium(vs, at, w, state.mis.r_u, rng, rays, true)[0], 0.0f) << i;
    sky_lit += direct_light_in_medium(vs, at, w, state.mis.r_u, rng, rays, true)[0] > 0.0f;
  }
  std::printf("kept collisions that reach the lamp: %d of %d; the sky, without it: %d\n", connected, kHops, sky_lit);
  EXPECT_GT(connected, kHops / 20);
  EXPECT_GT(sky_lit, kHops / 20);
}

// Bit for bit at one and two threads, over two sample ranges and over chunks of tables: the tables
// come from the seed and the sample index alone.
TEST(ShellTransport, TheSameImageAtAnyThreadCountSampleSplitAndChunk) {
  SceneDesc desc = lit_milk_ball(true);
  desc.render.spp = 8;
  const RenderScene scene = compile(desc);
  RenderStats stats;
  RenderControl one, two;
  one.threads = 1;
  two.threads = 2;
  const Film a = render(scene, desc.render, one, stats), b = render(scene, desc.render, two, stats);
  FilmBuffer by_samples = make_film(scene, false);
  for (int s = 0; s < 8; s += 4)
    render_into(scene, desc.render, by_samples, PixelRegion::whole(scene.camera), {s, s + 4}, two, stats);
  const Film c = resolve(by_samples, 8);
  auto same = [](const Film& x, const Film& y) {
    return x.rgb.size() == y.rgb.size() && std::memcmp(x.rgb.data(), y.rgb.data(), x.rgb.size() * sizeof(float)) == 0;
  };
  EXPECT_TRUE(same(a, b)) << "threads";
  EXPECT_TRUE(same(a, c)) << "sample ranges";
  desc.render.shell_transport = false;
  const Film analog = render(compile(desc), desc.render, two, stats);
  EXPECT_FALSE(same(a, analog)) << "no sphere was taken";

  // A point lamp in the scene: spheres are taken (their kept collisions connect to it), and the
  // image is the same at one and two threads and over sample ranges.
  {
    const SceneDesc lit = lamp_lit_milk_ball(true);
    const RenderScene lit_scene = compile(lit);
    ASSERT_TRUE(ShellSet(lit_scene, lit.render.seed).keeps_collisions());
    const Film with = render(lit_scene, lit.render, two, stats);
    EXPECT_TRUE(same(with, render(lit_scene, lit.render, one, stats))) << "threads, with a point lamp";
    FilmBuffer split = make_film(lit_scene, false);
    for (int s = 0; s < lit.render.spp; s += 2)
      render_into(lit_scene, lit.render, split, PixelRegion::whole(lit_scene.camera), {s, s + 2}, two, stats);
    EXPECT_TRUE(same(with, resolve(split, lit.render.spp))) << "sample ranges, with a point lamp";
    const SceneDesc walked = lamp_lit_milk_ball(false);
    EXPECT_FALSE(same(with, render(compile(walked), walked.render, two, stats))) << "no sphere with a point lamp";
  }

  // A call of more samples than one chunk of tables (kShellChunkSamples) walks them chunk by
  // chunk: the same image as two calls split elsewhere.
  // (A 1 mm ball filling the frame: five classes fit, whose tables are a tenth of the 3 mm ball's
  // to make.) Spheres are taken in the second chunk too: its samples alone differ from the analog
  // walk's.
  desc = lit_milk_ball(true, "1 mm");
  desc.render.spp = kShellChunkSamples + 64;
  desc.camera.width_px = desc.camera.height_px = 2;
  desc.camera.fov_deg = 2.0;
  const RenderScene small = compile(desc);
  FilmBuffer one_call = make_film(small, false), two_calls = make_film(small, false);
  render_into(small, desc.render, one_call, PixelRegion::whole(small.camera), {0, desc.render.spp}, two, stats);
  const int half = desc.render.spp / 2;
  render_into(small, desc.render, two_calls, PixelRegion::whole(small.camera), {0, half}, two, stats);
  render_into(small, desc.render, two_calls, PixelRegion::whole(small.camera), {half, desc.render.spp}, two, stats);
  EXPECT_TRUE(same(resolve(one_call, desc.render.spp), resolve(two_calls, desc.render.spp))) << "chunks";
  const SampleRange tail{kShellChunkSamples, desc.render.spp};
  FilmBuffer tail_on = make_film(small, false), tail_off = make_film(small, false);
  render_into(small, desc.render, tail_on, PixelRegion::whole(small.camera), tail, two, stats);
  desc.render.shell_transport = false;
  render_into(compile(desc), desc.render, tail_off, PixelRegion::whole(small.camera), tail, two, stats);
  EXPECT_FALSE(same(resolve(tail_on, 64), resolve(tail_off, 64))) << "no sphere in the second chunk";
}

}  // namespace
}  // namespace bouguer
