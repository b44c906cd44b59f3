// Grid concentration fields (media/grid_field.h, io/vdb.h, #12): trilinear values against
// OpenVDB's own sampler, column densities against quadrature (exact: the interpolant is a cubic
// inside each cell), edge cases of the cell walk, grids sampling the analytic fields, and the
// majorants tracking draws with (media/majorant.h): one per cell the ray crosses.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "bouguer/io/vdb.h"
#include "bouguer/media/concentration_field.h"
#include "bouguer/media/majorant.h"
#include "bouguer/scene/loader.h"
#include "support/test_support.h"
#include "support/vdb_files.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

// The field as the scene loader makes it from `file` (with the optional transform JSON).
GridField load_grid(const fs::path& file, const std::string& extra = "") {
  const std::string json = R"({"media": {"g": {"ior": 1.5, "absorption": {"library": "red-glass", "concentration":
      {"field": "grid", "file": ")" + file.string() + "\"" + extra + R"(}}}}, "objects": []})";
  return std::get<GridField>(parse_scene(json, file.parent_path() / "s.json").media.at("g").field_absorbers.at(0).field);
}

// Breakpoints of the segment: where it crosses a node plane of the lattice (each axis on its own).
std::vector<double> crossings(const GridField& f, const Vec3& o, const Vec3& d, double t0, double t1) {
  std::vector<double> t = {t0, t1};
  const Vec3 p0 = f.index_at(o), e = f.index_per_m * d;
  for (int k = 0; k < 3; ++k) {
    if (e[k] == 0.0) continue;
    for (int n = 0; n < f.values->nodes[k]; ++n) {
      const double tn = (n - p0[k]) / e[k];
      if (tn > t0 && tn < t1) t.push_back(tn);
    }
  }
  std::sort(t.begin(), t.end());
  return t;
}

// ∫ c dt by Simpson's rule (exact for cubics) on each piece between crossings, from point values.
double piecewise_simpson(const ConcentrationField& f, const Vec3& o, const Vec3& d, double t0, double t1) {
  const std::vector<double> t = crossings(std::get<GridField>(f), o, d, t0, t1);
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < t.size(); ++i) {
    const double a = t[i], b = t[i + 1];
    sum += (b - a) / 6.0 *
           (concentration_at(f, o + d * a) + 4.0 * concentration_at(f, o + d * (0.5 * (a + b))) +
            concentration_at(f, o + d * b));
  }
  return sum;
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return normalize(Vec3{n(rng), n(rng), n(rng)});
}

class GridFieldTest : public testing::Test {
 protected:
  fs::path dir = test::scratch_dir(testing::UnitTest::GetInstance()->current_test_info()->name());
};

TEST_F(GridFieldTest, TrilinearValuesMatchOpenVdbsBoxSampler) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  test::VdbTestGrid g;
  g.voxel_m = {0.5e-3, 0.5e-3, 0.5e-3};
  g.origin_m = {0.001, -0.002, 0.0005};
  g.first = {-2, 1, 3};
  g.count = {5, 6, 4};
  g.value = [&](const Vec3&) { return u(rng) * 3.0; };
  const fs::path file = dir / "random.vdb";
  test::write_vdb_file(file, {g});
  const GridField f = load_grid(file);
  std::vector<Vec3> points;
  for (int i = 0; i < 2000; ++i)  // over the voxels and a voxel beyond each side
    points.push_back(g.origin_m + Vec3{(-4.0 + 9.0 * u(rng)) * 0.5e-3, (-1.0 + 10.0 * u(rng)) * 0.5e-3,
                                       (1.0 + 8.0 * u(rng)) * 0.5e-3});
  const std::vector<double> reference = test::openvdb_box_samples(file, "density", points);
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_NEAR(concentration_at(f, points[i]), reference[i], 1e-5) << i;
}

TEST_F(GridFieldTest, ColumnDensityIsExactAlongRandomRays) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  test::VdbTestGrid g;
  g.voxel_m = {1e-3, 0.4e-3, 2e-3};  // anisotropic voxels, then a rotation and scale in the scene
  g.count = {9, 12, 7};
  g.value = [&](const Vec3&) { return u(rng) < 0.2 ? 0.0 : u(rng) * 5.0; };
  const fs::path file = dir / "random.vdb";
  test::write_vdb_file(file, {g});
  const ConcentrationField f =
      load_grid(file, R"(, "transform": [{"rotate_deg": [30, [1, 2, 3]]}, {"scale": [1.5, 0.7, 1.1]}, {"translate": [0.001, 0, 0]}])");
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 target{u(rng) * 0.012, u(rng) * 0.006, u(rng) * 0.016};
    const Vec3 d = random_unit(rng);
    const Vec3 o = target - d * 0.03;
    const double t0 = 0.03 * u(rng), t1 = 0.03 + 0.03 * u(rng);
    const double exact = column_density(f, o, d, t0, t1), reference = piecewise_simpson(f, o, d, t0, t1);
    EXPECT_NEAR(exact, reference, 1e-9 * reference + 1e-18) << i;
    if (reference > 0.0) ++hits;
  }
  EXPECT_GT(hits, 200);
}

TEST_F(GridFieldTest, AxisParallelCornerAndMissingRays) {
  test::VdbTestGrid g;  // 1 mm voxels at 0..3 mm: value 1 + i + 2j + 4k
  g.value = [](const Vec3& x) { return 1.0 + std::round(x.x * 1e3) + 2.0 * std::round(x.y * 1e3) + 4.0 * std::round(x.z * 1e3); };
  const fs::path file = dir / "ramp.vdb";
  test::write_vdb_file(file, {g});
  const ConcentrationField f = load_grid(file);
  // Along x through the voxel row j = 1, k = 2 (a line of nodes, on the faces of 4 cells): the
  // row is 1 + i + 2 + 8 for i = 0..3, and falls linearly to 0 over the border voxel each side.
  const double row = (11.0 / 2 + 11.5 + 12.5 + 13.5 + 14.0 / 2) * 1e-3;  // trapezoids, 1 mm each
  EXPECT_NEAR(column_density(f, {-0.01, 0.001, 0.002}, {1, 0, 0}, 0.0, 0.03), row, 1e-15);
  EXPECT_NEAR(column_density(f, {0.02, 0.001, 0.002}, {-1, 0, 0}, 0.0, 0.03), row, 1e-15);
  // Through nodes only (the main diagonal, across cell corners): compare with quadrature.
  const Vec3 diagonal = normalize(Vec3{1, 1, 1});
  const Vec3 o{-0.002, -0.002, -0.002};
  EXPECT_NEAR(column_density(f, o, diagonal, 0.0, 0.02), piecewise_simpson(f, o, diagonal, 0.0, 0.02), 1e-15);
  EXPECT_GT(column_density(f, o, diagonal, 0.0, 0.02), 0.0);
  // Misses: beside the grid, parallel to a face just outside it, and stopping before it.
  EXPECT_EQ(column_density(f, {-0.01, 0.0051, 0.0}, {1, 0, 0}, 0.0, 0.03), 0.0);
  EXPECT_EQ(column_density(f, {-0.01, 0.01, 0.01}, normalize(Vec3{1, 0.1, 0.1}), 0.0, 0.03), 0.0);
  EXPECT_EQ(column_density(f, {-0.01, 0.001, 0.002}, {1, 0, 0}, 0.0, 0.008), 0.0);
  EXPECT_EQ(max_concentration_on(f, {-0.01, 0.01, 0.01}, {1, 0, 0}, 0.0, 0.03), 0.0);
  // A ray exactly on the outer face of the lattice, where the border is zero.
  EXPECT_NEAR(column_density(f, {-0.01, -0.001, 0.002}, {1, 0, 0}, 0.0, 0.03), 0.0, 1e-15);
}

TEST_F(GridFieldTest, AScalingTransformScalesLengths) {
  test::VdbTestGrid g;
  g.value = [](const Vec3& x) { return 2.0 + 100.0 * x.y; };
  const fs::path file = dir / "g.vdb";
  test::write_vdb_file(file, {g});
  const ConcentrationField plain = load_grid(file), doubled = load_grid(file, R"(, "transform": [{"scale": 2}])");
  const Vec3 d = normalize(Vec3{1, 0.3, 0.2});
  const double a = column_density(plain, {-0.01, 0.0, 0.001}, d, 0.0, 0.05);
  EXPECT_NEAR(column_density(doubled, {-0.02, 0.0, 0.002}, d, 0.0, 0.1), 2.0 * a, 1e-14);
  EXPECT_NEAR(concentration_at(doubled, {0.004, 0.002, 0.006}), concentration_at(plain, {0.002, 0.001, 0.003}), 1e-12);
  // The scene's scale key and scaled() multiply the values; the maxima follow.
  const ConcentrationField tripled = load_grid(file, R"(, "scale": 3)");
  EXPECT_NEAR(column_density(tripled, {-0.01, 0.0, 0.001}, d, 0.0, 0.05), 3.0 * a, 1e-14);
  EXPECT_NEAR(column_density(scaled(plain, 0.5), {-0.01, 0.0, 0.001}, d, 0.0, 0.05), 0.5 * a, 1e-15);
  EXPECT_NEAR(max_concentration(tripled), 3.0 * (2.0 + 100.0 * 0.003), 1e-6);
}

TEST_F(GridFieldTest, MaxOnASegmentBoundsTheValuesThere) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  test::VdbTestGrid g;
  g.count = {6, 6, 6};
  g.value = [&](const Vec3&) { return u(rng) * 4.0; };
  const fs::path file = dir / "g.vdb";
  test::write_vdb_file(file, {g});
  const ConcentrationField f = load_grid(file);
  for (int i = 0; i < 200; ++i) {
    const Vec3 d = random_unit(rng), o = Vec3{0.003, 0.003, 0.003} - d * (0.006 * u(rng));
    const double t1 = 0.008 * u(rng), peak = max_concentration_on(f, o, d, 0.0, t1);
    EXPECT_LE(peak, max_concentration(f));
    for (int k = 0; k <= 100; ++k) EXPECT_LE(concentration_at(f, o + d * (t1 * k / 100.0)), peak + 1e-12) << i;
  }
}

// The tracking majorant of a grid (media/majorant.h): pieces in order, each bounding the density
// at every point of it, zero between them; its integral lies between the column density and that
// of the 8 equal pieces it replaces. A sparse random grid (70 % of the voxels empty) under a
// rotation and an anisotropic scale, so rays cross cells at every angle.
TEST_F(GridFieldTest, DdaMajorantBoundsTheDensityEverywhereOnRandomRays) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  test::VdbTestGrid g;
  g.count = {10, 7, 9};
  g.value = [&](const Vec3&) { return u(rng) < 0.7 ? 0.0 : u(rng) * 6.0; };
  const fs::path file = dir / "sparse.vdb";
  test::write_vdb_file(file, {g});
  const ConcentrationField f =
      load_grid(file, R"(, "transform": [{"rotate_deg": [40, [1, -1, 2]]}, {"scale": [1.2, 0.8, 1.0]}])");
  const double peak = max_concentration(f), slack = 1e-9 * peak;
  int pieces_seen = 0, empty_pieces = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 d = random_unit(rng), target{u(rng) * 0.01, u(rng) * 0.007, u(rng) * 0.009};
    const Vec3 o = target - d * (0.02 * u(rng));
    const double t_max = 0.03 * u(rng);
    DensityMajorant majorant(f, o, d, t_max);
    double previous_end = 0.0, integral = 0.0;
    for (MajorantSegment s; majorant.next(s);) {
      ASSERT_GE(s.t0, previous_end) << i;
      ASSERT_GT(s.t1, s.t0) << i;
      ASSERT_LE(s.t1, t_max) << i;
      for (int k = 0; k < 64 && s.t0 > previous_end; ++k) {  // a gap before the piece: no density there
        const double t = previous_end + (s.t0 - previous_end) * (k + 0.5) / 64.0;
        EXPECT_LE(concentration_at(f, o + d * t), slack) << i;
      }
      for (int k = 0; k <= 16; ++k) {  // the piece itself, ends included
        const double t = k == 16 ? s.t1 : s.t0 + (s.t1 - s.t0) * k / 16.0;
        EXPECT_LE(concentration_at(f, o + d * t), s.density + slack) << i << " piece " << pieces_seen;
      }
      EXPECT_LE(s.density, peak);
      integral += s.density * (s.t1 - s.t0);
      previous_end = s.t1;
      ++pieces_seen;
      if (s.density == 0.0) ++empty_pieces;
    }
    for (int k = 0; k < 64 && t_max > previous_end; ++k)  // after the last piece
      EXPECT_LE(concentration_at(f, o + d * (previous_end + (t_max - previous_end) * (k + 0.5) / 64.0)), slack) << i;
    double eight = 0.0;  // the 8 equal pieces of before
    for (int p = 0; p < kMajorantPieces; ++p) {
      const double a = t_max * p / kMajorantPieces, b = t_max * (p + 1) / kMajorantPieces;
      eight += max_concentration_on(f, o, d, a, b) * (b - a);
    }
    EXPECT_GE(integral, column_density(f, o, d, 0.0, t_max) * (1.0 - 1e-12)) << i;
    EXPECT_LE(integral, eight * (1.0 + 1e-12) + 1e-18) << i;
  }
  EXPECT_GT(pieces_seen, 1000);
  EXPECT_GT(empty_pieces, 100);  // the sparse cells are their own pieces, with nothing to track
}

// Grids that sample the analytic fields at their voxels: trilinear reproduces a linear field to
// rounding, and an erfc profile to (h/w)²/8 relative (h = 0.05 mm, w = 2 mm).
TEST_F(GridFieldTest, GridsSamplingAnalyticFieldsMatchTheirColumnDensities) {
  const FieldAxis axis{{0, 0.001, 0}, normalize(Vec3{0.02, 1, 0.01})};
  const std::pair<const char*, ConcentrationField> analytic[] = {{"linear", LinearField{axis, 2.0, 150.0}},
                                                                  {"diffusion", DiffusionField{axis, 2.0, 0.002}}};
  for (const auto& [name, field] : analytic) {
    test::VdbTestGrid g;
    g.voxel_m = {2e-3, 0.05e-3, 2e-3};
    g.origin_m = {-0.01, -0.005, -0.01};
    g.count = {11, 201, 11};
    g.value = [&](const Vec3& x) { return concentration_at(field, x); };
    const fs::path file = dir / (std::string(name) + ".vdb");
    test::write_vdb_file(file, {g});
    const ConcentrationField f = load_grid(file);
    const double tolerance = std::string(name) == "linear" ? 1e-6 : 5e-4;  // float voxels: 6e-8 relative
    for (const Vec3& d : {Vec3{0, 1, 0}, normalize(Vec3{0.3, 1, -0.2}), normalize(Vec3{0.1, -1, 0.05})}) {
      const Vec3 o = Vec3{0.001, 0.0, -0.002} - d * 0.0045;  // inside the grid from end to end
      const double exact = column_density(field, o, d, 0.0, 0.009), grid = column_density(f, o, d, 0.0, 0.009);
      EXPECT_NEAR(grid, exact, tolerance * exact) << name << " d.y " << d.y;
    }
  }
}

TEST_F(GridFieldTest, ColumnDensityTimePerRayOn64Cubed) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  test::VdbTestGrid g;
  g.count = {64, 64, 64};
  g.value = [&](const Vec3&) { return u(rng); };
  const fs::path file = dir / "64.vdb";
  test::write_vdb_file(file, {g});
  const ConcentrationField f = load_grid(file);
  std::vector<std::pair<Vec3, Vec3>> rays;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 d = random_unit(rng);
    rays.push_back({Vec3{0.032, 0.032, 0.032} - d * 0.06, d});  // through the centre, across the whole grid
  }
  double sum = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (const auto& [o, d] : rays) sum += column_density(f, o, d, 0.0, 0.12);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("column_density on a 64³ grid: %.2f µs per ray through the centre (mean column %.4g)\n",
              1e6 * seconds / double(rays.size()), sum / double(rays.size()));
  EXPECT_GT(sum, 0.0);
}

}  // namespace
}  // namespace bouguer
