#include <gtest/gtest.h>

#include "bouguer/core/strings.h"

namespace bouguer {
namespace {

TEST(Strings, EditDistance) {
  EXPECT_EQ(edit_distance("absorbtion", "absorption"), 1u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}

TEST(Strings, NearestNameSuggestsOnlyPlausibleMisspellings) {
  const std::vector<std::string> keys = {"absorption", "ior", "concentration"};
  EXPECT_EQ(nearest_name("absorbtion", keys), "absorption");
  EXPECT_EQ(nearest_name("concentraton", keys), "concentration");
  EXPECT_EQ(nearest_name("colour", keys), std::nullopt);
  EXPECT_EQ(suggestion("absorbtion", keys), " (did you mean 'absorption'?)");
  EXPECT_EQ(suggestion("colour", keys), " (known: absorption, ior, concentration)");
}

}  // namespace
}  // namespace bouguer
