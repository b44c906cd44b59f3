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

// What a reader quotes from a file: short, one line, never half a UTF-8 character.
TEST(Strings, ExcerptIsShortOneLineAndWholeCharacters) {
  EXPECT_EQ(excerpt("wavelength_nm"), "wavelength_nm");
  EXPECT_EQ(excerpt(std::string(50, 'x'), 10), "xxxxxxxxxx… (50 bytes)");
  EXPECT_EQ(excerpt("a\nb\tc\r\x01\x7f"), "a\\nb\\tc\\r\\x01\\x7f");
  EXPECT_EQ(excerpt(std::string("\0z", 2)), "\\x00z");
  EXPECT_EQ(excerpt("ab\xC3\xA9" "cd", 3), "ab… (6 bytes)");  // 'é' is two bytes: not cut in half
  EXPECT_EQ(excerpt("ab\xC3\xA9" "cd", 4), "ab\xC3\xA9" "… (6 bytes)");
}

}  // namespace
}  // namespace bouguer
