// Path guiding's SD-tree (render/path_guide.h): a direction tree's density integrates to one over
// the sphere and is the density its samples follow; refining it keeps its structure where the
// light is; the spatial tree halves its crowded cells and keeps every point in one cell; the same
// records in the same order give the same trees bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "bouguer/core/rng.h"
#include "bouguer/render/path_guide.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;

Vec3 direction(double cos_theta, double phi) {
  const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

// A tree that learned a bright narrow source about d0, a dimmer broad one about d1 and a little
// light everywhere, over two iterations (so it is refined where the light is).
DirectionTree learned_tree() {
  DirectionTree t;
  Rng rng(5, 1);
  const Vec3 d0 = normalize(Vec3{0.3, -0.2, 0.93}), d1 = normalize(Vec3{-0.6, 0.5, -0.2});
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < 20000; ++i) {
      const double u = rng.next_double(), v = rng.next_double();
      const Vec3 uniform = direction(2.0 * u - 1.0, 2.0 * kPi * v);
      t.add(uniform, 0.1);
      t.add(normalize(d0 + uniform * 0.05), 5.0);
      t.add(normalize(d1 + uniform * 0.4), 1.0);
    }
    if (pass == 0) t = t.refined(PathGuide::kDirectionRho);  // (a refined tree has zero sums)
  }
  return t;
}

TEST(DirectionTree, ItsDensityIntegratesToOneOverTheSphere) {
  const DirectionTree t = learned_tree();
  ASSERT_GT(t.node_count(), 20u) << "the tree was not refined where the light is";
  // The midpoint rule on the equal-area square, fine enough that every cell of depth ≤ 10 is
  // resolved exactly (2^11 × 2^11 points, dω = 4π / n).
  const int n = 2048;
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      sum += t.pdf(direction(2.0 * (i + 0.5) / n - 1.0, 2.0 * kPi * (j + 0.5) / n));
  EXPECT_NEAR(sum * 4.0 * kPi / (static_cast<double>(n) * n), 1.0, 2e-3);
}

// A density that does not match the samples (a cell's quadrant order, the 4^depth factor, the
// equal-area map) shows as bins whose counts miss their expectation by many standard deviations.
TEST(DirectionTree, ItsSamplesFollowItsDensity) {
  const DirectionTree t = learned_tree();
  constexpr int kBins = 16;  // 16 × 16 bins of equal solid angle
  std::vector<double> expected(kBins * kBins, 0.0), seen(kBins * kBins, 0.0);
  const int m = 32;  // points per bin side for the expectation
  for (int bi = 0; bi < kBins; ++bi)
    for (int bj = 0; bj < kBins; ++bj) {
      double p = 0.0;
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j)
          p += t.pdf(direction(2.0 * (bi + (i + 0.5) / m) / kBins - 1.0, 2.0 * kPi * (bj + (j + 0.5) / m) / kBins));
      expected[static_cast<std::size_t>(bi * kBins + bj)] = p / (m * m) * 4.0 * kPi / (kBins * kBins);
    }
  Rng rng(9, 2);
  const int samples = 400000;
  for (int s = 0; s < samples; ++s) {
    const Vec3 d = t.sample(rng.next_double(), rng.next_double(), rng.next_double());
    ASSERT_NEAR(length(d), 1.0, 1e-9);
    ASSERT_GT(t.pdf(d), 0.0) << "a sample where the density is 0";
    double phi = std::atan2(d.y, d.x);
    if (phi < 0.0) phi += 2.0 * kPi;
    const int bi = std::min(kBins - 1, static_cast<int>((d.z + 1.0) / 2.0 * kBins));
    const int bj = std::min(kBins - 1, static_cast<int>(phi / (2.0 * kPi) * kBins));
    seen[static_cast<std::size_t>(bi * kBins + bj)] += 1.0;
  }
  double worst = 0.0;
  for (std::size_t b = 0; b < seen.size(); ++b) {
    const double mean = expected[b] * samples;
    if (mean < 5.0) {
      EXPECT_LT(seen[b], 5.0 + 6.0 * std::sqrt(5.0));
      continue;
    }
    worst = std::max(worst, std::abs(seen[b] - mean) / std::sqrt(mean));
  }
  // 256 bins: a 5-σ excursion by chance has odds of about 1e-4.
  EXPECT_LT(worst, 5.0);
}

TEST(DirectionTree, ANewTreeHasNoDensityAndRefiningSplitsOnlyWhereTheLightIs) {
  DirectionTree t;
  EXPECT_EQ(t.total(), 0.0);
  EXPECT_EQ(t.pdf(Vec3{0, 0, 1}), 0.0);
  // All the light from one direction: refining spreads an old leaf's sum evenly over its
  // quadrants for the decision (Müller et al.'s build), so the first refinement splits the cells
  // about d four levels deep (each holds 4^-k > ρ of the total for k ≤ 3): 1 + 1 + 4 + 16 + 64
  // nodes, and d's cell is 4^-5 of the square. The next refinement, with the light again at d,
  // keeps only the chain of cells about d and goes four levels deeper there: never a full tree.
  const Vec3 d = normalize(Vec3{0.1, 0.2, 0.97});
  t.add(d, 1.0);
  DirectionTree r = t.refined(PathGuide::kDirectionRho);
  EXPECT_EQ(r.total(), 0.0);
  EXPECT_EQ(r.node_count(), 86u);
  r.add(d, 1.0);
  EXPECT_NEAR(r.pdf(d), std::pow(4.0, 5) / (4.0 * kPi), 1e-9);
  DirectionTree deep = r.refined(PathGuide::kDirectionRho);
  EXPECT_EQ(deep.node_count(), 5u + 85u);
  deep.add(d, 1.0);
  EXPECT_NEAR(deep.pdf(d), std::pow(4.0, 9) / (4.0 * kPi), 1e-6);
  // Down to kMaxDepth and no further.
  for (int i = 0; i < 8; ++i) deep = deep.refined(PathGuide::kDirectionRho), deep.add(d, 1.0);
  EXPECT_NEAR(deep.pdf(d), std::pow(4.0, DirectionTree::kMaxDepth) / (4.0 * kPi), 1e-6 * std::pow(4.0, 20));
}

std::vector<GuideRecord> records(std::uint64_t seed, int n) {
  Rng rng(seed, 3);
  std::vector<GuideRecord> r;
  for (int i = 0; i < n; ++i) {
    // Crowded near x = 0.7 (a small bright region), the rest spread over the cube.
    const bool crowd = i % 4 != 0;
    const double s = crowd ? 0.05 : 1.0;
    const Vec3f p{static_cast<float>((crowd ? 0.7 : 0.0) + s * (2.0 * rng.next_double() - 1.0)),
                  static_cast<float>(s * (2.0 * rng.next_double() - 1.0)), static_cast<float>(s * (2.0 * rng.next_double() - 1.0))};
    const Vec3 d = direction(2.0 * rng.next_double() - 1.0, 2.0 * kPi * rng.next_double());
    r.push_back({p, Vec3f{static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)},
                 static_cast<float>(rng.next_double())});
  }
  return r;
}

TEST(PathGuide, HalvesItsCrowdedCellsAndLearnsTheSameFromTheSameRecords) {
  PathGuide a(Vec3{0, 0, 0}, 1.0), b(Vec3{0, 0, 0}, 1.0);
  EXPECT_EQ(a.at(Vec3{0.7, 0, 0}), nullptr) << "an untrained guide guides nothing";
  const auto r = records(11, 60000);
  a.add(r), b.add(r);
  a.end_iteration(0), b.end_iteration(0);
  // 45 000 records in a cube of side 0.1 and 15 000 over the rest: the crowd's cells are halved
  // until each took at most 4000 (at least 16 of them), the rest less.
  EXPECT_GE(a.leaf_count(), 16u);
  EXPECT_EQ(a.leaf_count(), b.leaf_count());
  const DirectionTree* ta = a.at(Vec3{0.7, 0.01, 0.0});
  const DirectionTree* tb = b.at(Vec3{0.7, 0.01, 0.0});
  ASSERT_NE(ta, nullptr);
  ASSERT_NE(tb, nullptr);
  EXPECT_NE(ta, a.at(Vec3{-0.7, 0.5, 0.5})) << "the crowd and the far corner share a cell";
  for (double c = -0.95; c < 1.0; c += 0.1) {
    const Vec3 d = direction(c, 3.0 * c + 1.0);
    EXPECT_EQ(ta->pdf(d), tb->pdf(d));  // bit for bit
  }
  // Points outside the cube fall in its nearest cells.
  EXPECT_NE(a.at(Vec3{5.0, 0.0, 0.0}), nullptr);
  EXPECT_LT(a.bytes(), 64u << 20);
}

}  // namespace
}  // namespace bouguer
