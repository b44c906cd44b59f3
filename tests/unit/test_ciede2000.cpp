#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "bouguer/spectra/cielab.h"
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

}  // namespace
}  // namespace bouguer
