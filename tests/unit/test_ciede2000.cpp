#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "bouguer/render/compare.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

// Sharma, Wu, Dalal (2005), Table 1: all 34 pairs, in both orders, to 1e-4.
TEST(Ciede2000, ReproducesSharmaTestData) {
  std::ifstream in(test::test_data("ciede2000/sharma2005.tsv"));
  ASSERT_TRUE(in) << "missing Sharma test data";
  std::string line;
  int pairs = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'L') continue;
    std::istringstream row(line);
    Lab a, b;
    double expected = 0.0;
    row >> a.L >> a.a >> a.b >> b.L >> b.a >> b.b >> expected;
    ASSERT_TRUE(row) << line;
    EXPECT_NEAR(ciede2000(a, b), expected, 1e-4) << "pair " << pairs + 1;
    EXPECT_NEAR(ciede2000(b, a), expected, 1e-4) << "pair " << pairs + 1 << " reversed";
    ++pairs;
  }
  EXPECT_EQ(pairs, 34);
}

TEST(Ciede2000, IdenticalColoursHaveZeroDifference) {
  EXPECT_EQ(ciede2000({50, 10, -20}, {50, 10, -20}), 0.0);
  EXPECT_EQ(ciede2000({0, 0, 0}, {0, 0, 0}), 0.0);
}

// compare_images' two parts: greys that differ (the same a*, b* = 0) differ in lightness alone, a
// red and a green of the same luminance (so the same L*) in colour alone,
// and any two colours by both, in quadrature.
TEST(Compare, SplitsLightnessFromColour) {
  Film a(2, 1), b(2, 1);
  a.set_rgb(0, 0, {0.5f, 0.5f, 0.5f});
  b.set_rgb(0, 0, {0.6f, 0.6f, 0.6f});
  a.set_rgb(1, 0, {0.3f, 0.3f, 0.3f});
  b.set_rgb(1, 0, {0.2f, 0.2f, 0.2f});
  ImageDifference d = compare_images(a, b);
  EXPECT_GT(d.mean, 1.0);
  EXPECT_NEAR(d.mean_lightness, d.mean, 1e-9);
  EXPECT_NEAR(d.mean_colour, 0.0, 1e-9);
  const double y_red = linear_rgb_to_xyz(kRec709, {1.0, 0.0, 0.0}).y;
  const double y_green = linear_rgb_to_xyz(kRec709, {0.0, 1.0, 0.0}).y;
  const float red = 0.5f, green = static_cast<float>(0.5 * y_red / y_green);
  a.set_rgb(0, 0, {red, 0.0f, 0.0f});
  b.set_rgb(0, 0, {0.0f, green, 0.0f});
  a.set_rgb(1, 0, {0.0f, green, 0.0f});
  b.set_rgb(1, 0, {red, 0.0f, 0.0f});
  d = compare_images(a, b);
  EXPECT_GT(d.mean, 50.0);
  EXPECT_NEAR(d.mean_lightness, 0.0, 1e-3);
  EXPECT_NEAR(d.mean_colour, d.mean, 1e-3 * d.mean);
  // Any two colours: the parts add in quadrature, pixel by pixel.
  Film c(1, 1), e(1, 1);
  c.set_rgb(0, 0, {0.7f, 0.35f, 0.1f});
  e.set_rgb(0, 0, {0.4f, 0.5f, 0.3f});
  d = compare_images(c, e);
  EXPECT_GT(d.mean_lightness, 1.0);
  EXPECT_GT(d.mean_colour, 1.0);
  EXPECT_NEAR(d.mean * d.mean, d.mean_lightness * d.mean_lightness + d.mean_colour * d.mean_colour,
              1e-9 * d.mean * d.mean);
}

}  // namespace
}  // namespace bouguer
