// Analytic spheres, cylinders and disks (geometry/analytic.h through RayScene's Embree user
// geometry): closed-form hits, exact normals under any transform, a backlit absorbing glass ball
// against its closed form, a ball lens's focal length, and set-up no dearer than a box.
#include <gtest/gtest.h>

#include <chrono>
#include <numbers>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/geometry/analytic.h"
#include "bouguer/geometry/ray_scene.h"
#include "bouguer/geometry/shapes.h"
#include "bouguer/materials/fresnel.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(AnalyticSurface, SphereHitsFromOutsideAndInside) {
  const SphereSurface s{0.5};
  // From outside through the centre: the near side at 3 − 0.5, normal facing the ray.
  const auto near = intersect_local(s, {0, 0, 3}, {0, 0, -1}, 0.0, kInf);
  ASSERT_TRUE(near);
  EXPECT_DOUBLE_EQ(near->t, 2.5);
  EXPECT_NEAR(length(near->normal - Vec3{0, 0, 1}), 0.0, 1e-15);
  // From the centre: the far side, outward normal along the ray.
  const auto inside = intersect_local(s, {0, 0, 0}, {0.6, 0.8, 0}, 0.0, kInf);
  ASSERT_TRUE(inside);
  EXPECT_NEAR(inside->t, 0.5, 1e-15);
  EXPECT_NEAR(length(inside->normal - Vec3{0.6, 0.8, 0}), 0.0, 1e-15);
  // Starting a hair outside the surface and leaving: nothing (no self-hit).
  EXPECT_FALSE(intersect_local(s, {0, 0, 0.5 + 1e-12}, {0, 0, 1}, 0.0, kInf));
  // Passing beside it, and a hit beyond t_max.
  EXPECT_FALSE(intersect_local(s, {0.51, 0, 3}, {0, 0, -1}, 0.0, kInf));
  EXPECT_FALSE(intersect_local(s, {0, 0, 3}, {0, 0, -1}, 0.0, 2.4));
  // A ray from a million radii away still hits within rounding (no cancellation in b² − ac).
  const auto far = intersect_local(s, {0.3, 0, 5e5}, {0, 0, -1}, 0.0, kInf);
  ASSERT_TRUE(far);
  EXPECT_NEAR(far->point.z, 0.4, 1e-9);
}

TEST(AnalyticSurface, CylinderSideAndCaps) {
  const CylinderSurface c{0.5, 2.0};
  const auto side = intersect_local(c, {3, 1, 0}, {-1, 0, 0}, 0.0, kInf);
  ASSERT_TRUE(side);
  EXPECT_DOUBLE_EQ(side->t, 2.5);
  EXPECT_EQ(side->part, AnalyticPart::side);
  EXPECT_NEAR(length(side->normal - Vec3{1, 0, 0}), 0.0, 1e-15);
  const auto top = intersect_local(c, {0.2, 5, 0.1}, {0, -1, 0}, 0.0, kInf);
  ASSERT_TRUE(top);
  EXPECT_DOUBLE_EQ(top->t, 3.0);
  EXPECT_EQ(top->part, AnalyticPart::top);
  EXPECT_EQ(top->normal, (Vec3{0, 1, 0}));
  const auto bottom = intersect_local(c, {0.2, 1, 0.1}, {0, -1, 0}, 0.0, kInf);  // from inside
  ASSERT_TRUE(bottom);
  EXPECT_DOUBLE_EQ(bottom->t, 1.0);
  EXPECT_EQ(bottom->part, AnalyticPart::bottom);
  EXPECT_EQ(bottom->normal, (Vec3{0, -1, 0}));
  // Past the end of the tube, beside the caps.
  EXPECT_FALSE(intersect_local(c, {3, 2.1, 0}, {-1, 0, 0}, 0.0, kInf));
}

TEST(AnalyticSurface, DiskIsOneFlatCircle) {
  const DiskSurface d{1.0};
  const auto h = intersect_local(d, {0.6, 0.7, 2}, {0, 0, -1}, 0.0, kInf);
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->t, 2.0);
  EXPECT_EQ(h->normal, (Vec3{0, 0, 1}));
  EXPECT_FALSE(intersect_local(d, {0.8, 0.7, 2}, {0, 0, -1}, 0.0, kInf));  // outside the rim
  EXPECT_FALSE(intersect_local(d, {0, 0, 2}, {1, 0, 0}, 0.0, kInf));       // parallel
}

// Through RayScene: a sphere stretched into an ellipsoid, turned and moved. The hit lies on the
// ellipsoid, its normal is the gradient of the ellipsoid's equation, and a triangle in front of
// it hides it.
TEST(AnalyticSurface, TransformedSphereInRayScene) {
  const Transform t = Transform::scale({2.0, 1.0, 0.5})
                          .then(Transform::rotate_deg(30.0, {0, 0, 1}))
                          .then(Transform::translate({1, 2, 3}));
  RayScene scene;
  const std::uint32_t id = scene.add(AnalyticShape{SphereSurface{1.0}, t});
  scene.commit();
  const Mat3 to_local = inverse(t.linear);
  for (const Vec3 d : {Vec3{0, 0, -1}, normalize(Vec3{0.15, -0.05, -1}), normalize(Vec3{-0.1, 0.08, -1})}) {
    const auto h = scene.intersect({Vec3{1, 2, 10}, d});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->geometry, id);
    const Vec3 q = to_local * (h->point - t.translation);
    EXPECT_NEAR(length(q), 1.0, 1e-12);
    EXPECT_NEAR(length(h->point - (Vec3{1, 2, 10} + d * h->t)), 0.0, 1e-12);
    // ∇(|M⁻¹(p − c)|²) ∝ M⁻ᵀ M⁻¹ (p − c).
    Vec3 gradient;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) gradient[static_cast<std::size_t>(i)] += to_local.m[k][i] * q[static_cast<std::size_t>(k)];
    EXPECT_NEAR(length(h->normal - normalize(gradient)), 0.0, 1e-12);
    EXPECT_EQ(h->shading_normal, h->normal);
  }
  // A mirroring transform keeps the normal outward (the inverse transpose needs no flip).
  RayScene mirrored;
  mirrored.add(AnalyticShape{SphereSurface{1.0}, Transform::scale({-1.0, 1.0, 1.0})});
  mirrored.commit();
  const auto m = mirrored.intersect({Vec3{0.3, 0.2, 5}, Vec3{0, 0, -1}});
  ASSERT_TRUE(m);
  EXPECT_GT(dot(m->normal, m->point), 0.99);
  const auto [lo, hi] = scene.bounds(id);
  EXPECT_LE(lo.z, 3.0 - 0.5);
  EXPECT_GE(hi.z, 3.0 + 0.5);

  RayScene both;
  both.add(AnalyticShape{SphereSurface{1.0}, Transform::translate({0, 0, 0})});
  Mesh screen;
  screen.positions = {{-5, -5, 2}, {5, -5, 2}, {0, 5, 2}};
  screen.triangles = {{0, 1, 2}};
  const std::uint32_t screen_id = both.add(screen);
  both.commit();
  const auto h = both.intersect({Vec3{0, 0, 10}, Vec3{0, 0, -1}});
  ASSERT_TRUE(h);
  EXPECT_EQ(h->geometry, screen_id);
  const auto behind = both.intersect({Vec3{0, 0, 1.5}, Vec3{0, 0, -1}});
  ASSERT_TRUE(behind);
  EXPECT_EQ(behind->geometry, 0u);
  EXPECT_DOUBLE_EQ(behind->t, 0.5);
}

// Where a ray parallel to the axis (−z) at height h crosses the axis after refracting into and
// out of the first geometry it meets; nullopt when it does not come out converging.
std::optional<double> axis_crossing_z(const RayScene& scene, double h, double n) {
  Ray ray{{h, 0, 1.0}, {0, 0, -1}};
  for (const auto& [eta_i, eta_t] : {std::pair{1.0, n}, std::pair{n, 1.0}}) {
    const auto hit = scene.intersect(ray);
    if (!hit) return std::nullopt;
    const Vec3 facing = dot(hit->normal, ray.direction) < 0.0 ? hit->normal : -hit->normal;
    const auto t = refract(-ray.direction, facing, eta_i, eta_t);
    if (!t) return std::nullopt;
    ray = {offset_ray_origin(*hit, *t), *t};
  }
  if (!(ray.direction.x < 0.0)) return std::nullopt;
  return ray.origin.z - ray.origin.x * ray.direction.z / ray.direction.x;
}

// The distance from a point to each analytic surface in its local frame, in closed form.
TEST(AnalyticSurface, DistancesInClosedForm) {
  EXPECT_DOUBLE_EQ(distance_local(SphereSurface{2.0}, {0, 0, 0}), 2.0);
  EXPECT_DOUBLE_EQ(distance_local(SphereSurface{2.0}, {0, 3, 4}), 3.0);
  const CylinderSurface cyl{1.0, 4.0};
  EXPECT_DOUBLE_EQ(distance_local(cyl, {0, 2, 0}), 1.0);        // on the axis, halfway: the side
  EXPECT_DOUBLE_EQ(distance_local(cyl, {0, 0.25, 0}), 0.25);    // near the bottom cap
  EXPECT_DOUBLE_EQ(distance_local(cyl, {0.5, 4.5, 0}), 0.5);    // above the top cap
  EXPECT_DOUBLE_EQ(distance_local(cyl, {4, 2, 0}), 3.0);        // beside the side
  EXPECT_DOUBLE_EQ(distance_local(cyl, {0, -4, 4}), 5.0);       // beyond the bottom rim
  EXPECT_DOUBLE_EQ(distance_local(DiskSurface{1.0}, {0.5, 0, -2}), 2.0);
  EXPECT_DOUBLE_EQ(distance_local(DiskSurface{1.0}, {4, 0, 4}), 5.0);
  // The nearest points themselves: on the surface, at that distance.
  auto nearest_is = [](const AnalyticSurface& s, const Vec3& p, const Vec3& expected) {
    const Vec3 n = nearest_local(s, p);
    EXPECT_NEAR(length(n - expected), 0.0, 1e-15) << p.x << " " << p.y << " " << p.z;
    EXPECT_NEAR(length(p - n), distance_local(s, p), 1e-15);
  };
  nearest_is(SphereSurface{2.0}, {0, 3, 4}, {0, 1.2, 1.6});
  nearest_is(cyl, {0.5, 2, 0}, {1, 2, 0});
  nearest_is(cyl, {0.2, 0.1, 0}, {0.2, 0, 0});
  nearest_is(cyl, {0.5, 4.5, 0}, {0.5, 4, 0});
  nearest_is(cyl, {4, 2, 0}, {1, 2, 0});
  nearest_is(cyl, {0, -4, 4}, {0, 0, 1});
  nearest_is(DiskSurface{1.0}, {0.5, 0, -2}, {0.5, 0, 0});
  nearest_is(DiskSurface{1.0}, {4, 0, 4}, {1, 0, 0});
  EXPECT_NEAR(length(nearest_local(SphereSurface{2.0}, {0, 0, 0})), 2.0, 1e-15);
}

// Through RayScene, an analytic surface placed by an affine transform: a rotated, uniformly scaled
// sphere gives its exact distance (to rounding); a sphere stretched
// into an ellipsoid gives a lower bound, never above the distance to any of its surface points.
TEST(AnalyticSurface, DistanceThroughATransformIsALowerBound) {
  RayScene round, ellipsoid;
  round.add(AnalyticShape{SphereSurface{1.0}, Transform::scale({2, 2, 2})
                                                    .then(Transform::rotate_deg(40.0, {1, 1, 0}))
                                                    .then(Transform::translate({1, 0, 0}))});
  round.commit();
  const Transform t = Transform::scale({3.0, 1.0, 0.5}).then(Transform::rotate_deg(30.0, {0, 0, 1}));
  ellipsoid.add(AnalyticShape{SphereSurface{1.0}, t});
  ellipsoid.commit();
  for (const Vec3 p : {Vec3{1, 0, 0}, Vec3{1.5, 0.5, 0.2}, Vec3{5, -3, 1}}) {
    const double exact = std::abs(length(p - Vec3{1, 0, 0}) - 2.0);
    Vec3 nearest;
    EXPECT_LE(round.distance_to_surfaces(p, 100.0, &nearest), exact * (1 + 1e-12));
    EXPECT_NEAR(length(nearest - Vec3{1, 0, 0}), 2.0, 1e-12);  // on the sphere, at the distance
    EXPECT_NEAR(length(p - nearest), exact, 1e-12);
    EXPECT_GE(round.distance_to_surfaces(p, 100.0), exact * (1 - 1e-8));
  }
  for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 0.2, 0.1}, Vec3{4, 1, 0}, Vec3{0, 0, 2}}) {
    double nearest = 1e300;
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; j < 400; ++j) {
        const double theta = std::numbers::pi * i / 200, phi = 2 * std::numbers::pi * j / 400;
        const Vec3 s = t.apply({std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
        nearest = std::min(nearest, length(p - s));
      }
    const double bound = ellipsoid.distance_to_surfaces(p, 100.0);
    EXPECT_LE(bound, nearest) << p.x;
  }
  // At the centre the nearest point is on the shortest axis: the bound is exact there.
  EXPECT_NEAR(ellipsoid.distance_to_surfaces({0, 0, 0}, 100.0), 0.5, 1e-8);
  // A cylinder and a disk a kilometre from the origin, rotated and stretched (the disk 10⁴ times
  // thinner in z, which does not change it): never above the distance to sampled surface points.
  RayScene far;
  const Vec3 at{1000.0, -500.0, 250.0};
  const Transform tc = Transform::scale({1.0, 2.0, 0.5}).then(Transform::rotate_deg(25.0, {1, 0, 1})).then(Transform::translate(at));
  const Transform td = Transform::scale({10.0, 10.0, 1e-3}).then(Transform::rotate_deg(60.0, {0, 1, 0})).then(Transform::translate(at + Vec3{0, 30, 0}));
  far.add(AnalyticShape{CylinderSurface{1.0, 3.0}, tc});
  far.add(AnalyticShape{DiskSurface{1.0}, td});
  far.commit();
  std::vector<Vec3> surface;
  for (int i = 0; i <= 60; ++i)
    for (int j = 0; j < 120; ++j) {
      const double a = 2 * std::numbers::pi * j / 120, f = i / 60.0;
      surface.push_back(tc.apply({std::cos(a), 3.0 * f, std::sin(a)}));                        // side
      surface.push_back(tc.apply({f * std::cos(a), 0.0, f * std::sin(a)}));                    // bottom cap
      surface.push_back(tc.apply({f * std::cos(a), 3.0, f * std::sin(a)}));                    // top cap
      surface.push_back(td.apply({f * std::cos(a), f * std::sin(a), 0.0}));                    // disk
    }
  for (const Vec3 d : {Vec3{0, 1.5, 0}, Vec3{0.3, 1, 0.2}, Vec3{3, 0, 0}, Vec3{0, 30, 2}, Vec3{5, 28, -1}}) {
    double nearest = 1e300;
    for (const Vec3& s : surface) nearest = std::min(nearest, length(at + d - s));
    const double bound = far.distance_to_surfaces(at + d, 1e6);
    EXPECT_LE(bound, nearest) << d.x << " " << d.y;
    EXPECT_GT(bound, 0.0) << d.x << " " << d.y;
  }
}

// A ball lens (n = 1.5, R = 1 cm) focuses a distant light at f = nR / (2(n − 1)) from its centre
// (paraxial). Rays parallel to the axis at heights h ≤ 0.02 R, refracted twice through the
// RayScene's hits, cross the axis within their spherical aberration, about (h/R)²·R/2 of f. The
// same rays through the 96-segment tessellated ball, for contrast, miss by more.
TEST(AnalyticSurface, BallLensFocusesAtItsParaxialFocalLength) {
  const double radius = 0.01, n = 1.5;
  RayScene exact, faceted;
  exact.add(AnalyticShape{SphereSurface{radius}, Transform{}});
  exact.commit();
  faceted.add(make_shape(SphereShape{radius, 96, true}, "ball").front().mesh);
  faceted.commit();
  const double f = n * radius / (2.0 * (n - 1.0));
  double faceted_worst = 0.0;
  for (const double h : {0.005 * radius, 0.01 * radius, 0.02 * radius}) {
    const double tolerance = 0.6 * (h / radius) * (h / radius) * radius + 1e-9 * f;
    const auto z = axis_crossing_z(exact, h, n);
    ASSERT_TRUE(z) << "h = " << h;
    EXPECT_NEAR(-*z, f, tolerance) << "h = " << h;
    const auto zf = axis_crossing_z(faceted, h, n);
    faceted_worst = std::max(faceted_worst, zf ? std::abs(-*zf - f) / tolerance : kInf);
  }
  std::printf("ball lens: the faceted ball misses f by up to %.3g tolerances\n", faceted_worst);
  EXPECT_GT(faceted_worst, 1.0);
}

// A glass ball (n = 1.5, σ_a = 40 /m, R = 1 cm) in a uniform white background, seen by an
// orthographic camera across its middle 80 %. A ray at distance x from the axis meets the
// surface at sin θ = x/R; inside, every chord has the same length 2R cos θt and every internal
// reflection the same reflectance R(θ), so the pixel is the background times
//   R(θ) + (1 − R(θ))² τ / (1 − R(θ) τ),   τ = exp(−σ_a · 2R cos θt)
// (the outer reflection, the first transmission and every internal reflection; the problem
// statement's (1 − R)²τ plus the first internal reflection are its leading terms). Each pixel of
// the row through the centre is compared with that closed form averaged over the pixel.
TEST(AnalyticSurface, BacklitAbsorbingGlassBallMatchesItsClosedForm) {
  constexpr int kPixels = 21;
  const double radius = 0.01, n = 1.5, sigma_a = 40.0, view = 1.6 * radius;
  const std::string exact = fmt::format(R"({{"type": "sphere", "radius": {}}})", radius);
  auto scene = [&](bool ball, const std::string& shape) {
    return fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "up": [0, 1, 0],
                  "width": {}, "resolution": [{}, {}]}},
      "render": {{"integrator": "whitted", "spectral": "rgb3", "spp": 64, "max_depth": 64}},
      "world_medium": "vacuum",
      "media": {{"glass": {{"ior": {}, "absorption": {{"unit": "attenuation_per_m",
                 "wavelength_nm": [360, 830], "value": [{}, {}]}}}}}},
      "objects": [{}],
      "background": {{"spectrum": "E", "scale": 1.0}}
    }})",
                       view, kPixels, kPixels, n, sigma_a, sigma_a,
                       ball ? fmt::format(R"({{"name": "ball", "shape": {}, "inside": "glass"}})", shape)
                            : std::string{});
  };
  const Film with = test::render_text(scene(true, exact));
  const Film without = test::render_text(scene(false, exact));
  auto closed_form = [&](double x, double y) {
    const double sin_i = std::hypot(x, y) / radius, cos_i = std::sqrt(1.0 - sin_i * sin_i);
    const double cos_t = cos_theta_transmitted(cos_i, 1.0, n);
    const double r = fresnel_dielectric(cos_i, cos_t, 1.0, n), tau = std::exp(-sigma_a * 2.0 * radius * cos_t);
    return r + (1.0 - r) * (1.0 - r) * tau / (1.0 - r * tau);
  };
  const double pixel = view / kPixels;
  double worst = 0.0;
  for (int px = 0; px < kPixels; ++px) {
    double expected = 0.0;
    constexpr int kSub = 16;
    for (int i = 0; i < kSub; ++i)
      for (int j = 0; j < kSub; ++j)
        expected += closed_form(-view / 2 + (px + (i + 0.5) / kSub) * pixel, ((j + 0.5) / kSub - 0.5) * pixel);
    expected /= kSub * kSub;
    const int py = kPixels / 2;
    for (int c = 0; c < 3; ++c) {
      const double measured = double(with.rgb_at(px, py)[static_cast<std::size_t>(c)]) /
                              double(without.rgb_at(px, py)[static_cast<std::size_t>(c)]);
      worst = std::max(worst, std::abs(measured / expected - 1.0));
      EXPECT_NEAR(measured / expected, 1.0, 0.005) << "pixel " << px << " channel " << c;
    }
  }
  std::printf("backlit glass ball: worst relative error over the centre row %.2e\n", worst);
  // The 96-segment tessellation, with its exact vertex normals as shading normals and, written to
  // an OBJ without them, with flat facets, against the analytic ball over the whole image. Measured:
  // smooth mean 0.08 %, worst 3.8 % (at the edge of the view, where the facets bend grazing rays;
  // 1.6 % with the sub-pixel strata taken in row order); flat mean 0.33 %, worst 8.3 %.
  std::array<double, 2> mean_error{}, worst_error{};
  const Mesh mesh = make_shape(SphereShape{radius, 96, true}, "ball").front().mesh;
  std::string obj;
  for (const Vec3& p : mesh.positions) obj += fmt::format("v {} {} {}\n", p.x, p.y, p.z);
  for (const auto& t : mesh.triangles) obj += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  const auto flat = test::scratch_dir("AnalyticSurface.Backlit") / "flat-ball.obj";
  test::write_file(flat, obj);
  for (const std::string& t : {fmt::format(R"({{"type": "sphere", "radius": {}, "tessellate": true, "segments": 96}})", radius),
                               fmt::format(R"({{"type": "mesh", "file": "{}"}})", flat.string())}) {
    const Film tess = test::render_text(scene(true, t));
    double worst_t = 0.0, mean_t = 0.0;
    for (int py = 0; py < kPixels; ++py)
      for (int px = 0; px < kPixels; ++px)
        for (int c = 0; c < 3; ++c) {
          const double a = double(with.rgb_at(px, py)[c]), b = double(tess.rgb_at(px, py)[c]);
          worst_t = std::max(worst_t, std::abs(b / a - 1.0));
          mean_t += std::abs(b / a - 1.0) / (3 * kPixels * kPixels);
        }
    std::printf("tessellated %s: worst %.3e mean %.3e vs analytic\n", t.c_str(), worst_t, mean_t);
    const std::size_t k = t.find("mesh") == std::string::npos ? 0 : 1;
    mean_error[k] = mean_t, worst_error[k] = worst_t;
  }
  EXPECT_LT(mean_error[0], 0.002);
  EXPECT_LT(worst_error[0], 0.05);
  EXPECT_GT(mean_error[1], 2.0 * mean_error[0]);  // the facets, which the shading normals remove
  EXPECT_GT(worst_error[1], 2.0 * worst_error[0]);
}

// A sphere is no dearer to set up than a box: no triangles kept, and its compile takes no longer
// (the fastest of five, with room for a loaded machine). The tessellated sphere keeps its triangles.
TEST(AnalyticSurface, SphereSetUpCostsNoMoreThanABox) {
  auto scene = [](const std::string& shape) {
    return parse_scene(fmt::format(R"({{"camera": {{"resolution": [8, 8]}}, "media": {{"glass": {{"ior": 1.5}}}},
        "objects": [{{"name": "o", "shape": {}, "inside": "glass"}}]}})",
                                       shape),
                           "setup.json");
  };
  auto fastest_compile_s = [](const SceneDesc& desc, std::size_t& stored) {
    double best = kInf;
    for (int i = 0; i < 5; ++i) {
      const auto start = std::chrono::steady_clock::now();
      const RenderScene s = compile(desc);
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      stored = s.rays.mesh(0).positions.size() + s.rays.mesh(0).triangles.size();
    }
    return best;
  };
  std::size_t sphere_stored = 0, box_stored = 0, tessellated_stored = 0;
  const double sphere_s = fastest_compile_s(scene(R"({"type": "sphere", "radius": 0.01})"), sphere_stored);
  const double box_s = fastest_compile_s(scene(R"({"type": "box", "size": [0.02, 0.02, 0.02]})"), box_stored);
  fastest_compile_s(scene(R"({"type": "sphere", "radius": 0.01, "tessellate": true})"), tessellated_stored);
  std::printf("set-up: sphere %.2f ms (%zu vertices and triangles kept), box %.2f ms (%zu)\n", 1e3 * sphere_s,
              sphere_stored, 1e3 * box_s, box_stored);
  EXPECT_EQ(sphere_stored, 0u);
  EXPECT_GT(box_stored, 0u);
  EXPECT_GT(tessellated_stored, 10000u);
  EXPECT_LT(sphere_s, 1.5 * box_s + 1e-3);
}

// The scene format: analytic by default, "tessellate" for triangles; a sphere or cylinder bounds a
// medium, a disk does not; an emitting sphere stays exact (one SphereLight, sampled by its solid
// angle) where it emits one-sided, untextured, and a transform keeps it a sphere; other emitters
// are triangles.
TEST(AnalyticSurface, SceneFormat) {
  auto compiled = [](const std::string& objects) {
    return compile(parse_scene(fmt::format(R"({{"camera": {{"resolution": [8, 8]}},
        "media": {{"glass": {{"ior": 1.5}}}}, "objects": [{}]}})",
                                               objects),
                                   "format.json"));
  };
  const RenderScene cylinder =
      compiled(R"({"name": "rod", "shape": {"type": "cylinder", "radius": 0.01, "height": 0.05}, "inside": "glass"})");
  EXPECT_TRUE(cylinder.rays.mesh(0).triangles.empty());
  const RenderScene lamp = compiled(R"({"name": "lamp", "shape": {"type": "sphere", "radius": 0.01},
                                        "transform": [{"scale": 2}, {"rotate_deg": [30, [1, 2, 3]]},
                                                      {"translate": [0.1, 0.2, 0.3]}],
                                        "emission": {"spectrum": "D65"}})");
  EXPECT_TRUE(lamp.rays.mesh(0).triangles.empty());
  ASSERT_EQ(lamp.surfaces[0].first_light, 0);
  const auto* sphere = std::get_if<SphereLight>(&lamp.lights[0]);
  ASSERT_NE(sphere, nullptr);
  EXPECT_NEAR(sphere->radius_m, 0.02, 1e-15);
  EXPECT_NEAR(length(sphere->centre_m - Vec3{0.1, 0.2, 0.3}), 0.0, 1e-15);
  for (const char* lamp_json : {R"({"name": "lamp", "shape": {"type": "sphere", "radius": 0.01},
                                   "emission": {"spectrum": "D65", "two_sided": true}})",
                                R"({"name": "lamp", "shape": {"type": "sphere", "radius": 0.01},
                                   "transform": [{"scale": [1, 2, 1]}], "emission": {"spectrum": "D65"}})",
                                R"({"name": "lamp", "shape": {"type": "sphere", "radius": 0.01, "tessellate": true},
                                   "emission": {"spectrum": "D65"}})"}) {
    const RenderScene tessellated = compiled(lamp_json);
    EXPECT_FALSE(tessellated.rays.mesh(0).triangles.empty()) << lamp_json;
    EXPECT_TRUE(std::holds_alternative<AreaLight>(tessellated.lights[0])) << lamp_json;
  }
  const RenderScene disk = compiled(R"({"name": "d", "shape": {"type": "disk", "radius": 0.01, "tessellate": true},
                                        "material": {"type": "diffuse", "reflectance": 0.5}})");
  EXPECT_EQ(disk.rays.mesh(0).triangles.size(), 128u);
  try {
    compiled(R"({"name": "d", "shape": {"type": "disk", "radius": 0.01}, "inside": "glass"})");
    FAIL() << "a disk bounded a medium";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a flat shape cannot bound medium 'glass'"), std::string::npos) << e.what();
  }
  try {
    compiled(R"({"name": "s", "shape": {"type": "sphere", "radius": 0.01, "tessellate": 1}, "inside": "glass"})");
    FAIL() << "a number taken for a boolean";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tessellate"), std::string::npos) << e.what();
  }
}

// A cylinder's side stays circular under a similarity and under any stretch along its axis (the
// world's radius the scale across it, the axis the image of +y from the base's centre); scaled
// unevenly across its axis, or sheared, it is elliptic: nothing.
TEST(Analytic, ACylindersSideIsCircularWhereTheTransformKeepsItSo) {
  const CylinderSurface c{0.1, 0.5};
  const Transform similar = Transform::scale({2, 2, 2}).then(Transform::rotate_deg(90, {0, 0, 1})).then(
      Transform::translate({1, 2, 3}));
  const auto a = circular_side(c, similar);
  ASSERT_TRUE(a);
  EXPECT_NEAR(a->radius_m, 0.2, 1e-15);
  EXPECT_NEAR(length(a->axis - Vec3{-1, 0, 0}), 0.0, 1e-12);
  EXPECT_NEAR(length(a->on_axis - Vec3{1, 2, 3}), 0.0, 1e-15);
  const auto stretched = circular_side(c, Transform::scale({3, 7, 3}).then(Transform::rotate_deg(30, {1, 0, 0})));
  ASSERT_TRUE(stretched);
  EXPECT_NEAR(stretched->radius_m, 0.3, 1e-15);
  EXPECT_NEAR(length(stretched->axis - Vec3{0, std::cos(std::numbers::pi / 6), std::sin(std::numbers::pi / 6)}), 0.0,
              1e-12);
  EXPECT_FALSE(circular_side(c, Transform::scale({2, 0.5, 3})));
  Transform shear;  // +y leaned towards +x
  shear.linear = Mat3::from_columns({1, 0, 0}, {0.2, 1, 0}, {0, 0, 1});
  EXPECT_FALSE(circular_side(c, shear));
}

}  // namespace
}  // namespace bouguer
