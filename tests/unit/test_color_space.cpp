#include <gtest/gtest.h>

#include <cmath>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

void expect_matrix_near(const Mat3& got, const Mat3& expected, double tolerance) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(got.m[i][j], expected.m[i][j], tolerance) << "[" << i << "][" << j << "]";
}

// IEC 61966-2-1:1999, the sRGB RGB -> XYZ matrix (4 decimals as published).
TEST(ColorSpace, Rec709MatrixMatchesIec61966) {
  const Mat3 expected{{{{0.4124, 0.3576, 0.1805}, {0.2126, 0.7152, 0.0722}, {0.0193, 0.1192, 0.9505}}}};
  expect_matrix_near(rgb_to_xyz_matrix(kRec709), expected, 1e-4);
}

// ITU-R BT.2087-0, linear Rec.709 -> linear Rec.2020 (4 decimals as published).
TEST(ColorSpace, Rec709ToRec2020MatchesBt2087) {
  const Mat3 expected{{{{0.6274, 0.3293, 0.0433}, {0.0691, 0.9195, 0.0114}, {0.0164, 0.0880, 0.8956}}}};
  expect_matrix_near(xyz_to_rgb_matrix(kRec2020) * rgb_to_xyz_matrix(kRec709), expected, 1e-4);
}

// SMPTE/ACES TB-2014-004: AP1 -> XYZ (ACES white).
TEST(ColorSpace, AcesCgMatrixMatchesAcesSpec) {
  const Mat3 expected{{{{0.6624541811, 0.1340042065, 0.1561876870},
                        {0.2722287168, 0.6740817658, 0.0536895174},
                        {-0.0055746495, 0.0040607335, 1.0103391003}}}};
  expect_matrix_near(rgb_to_xyz_matrix(kAcesCg), expected, 2e-5);
}

TEST(ColorSpace, D65WhiteIsRgbWhiteInEverySpace) {
  for (const ColorSpace* cs : {&kRec709, &kRec2020, &kAcesCg}) {
    const Vec3 rgb = xyz_to_linear_rgb(*cs, xy_to_xyz(kD65White.x, kD65White.y));
    EXPECT_NEAR(rgb.x, 1.0, 1e-12) << cs->name;
    EXPECT_NEAR(rgb.y, 1.0, 1e-12) << cs->name;
    EXPECT_NEAR(rgb.z, 1.0, 1e-12) << cs->name;
    const Vec3 back = linear_rgb_to_xyz(*cs, Vec3{0.2, 0.5, 0.9});
    const Vec3 again = xyz_to_linear_rgb(*cs, back);
    EXPECT_NEAR(again.x, 0.2, 1e-12);
    EXPECT_NEAR(again.z, 0.9, 1e-12);
  }
}

// Bradford D65 -> D50 as tabulated by B. Lindbloom (whites X,Z = 0.95047,1.08883 and 0.96422,0.82521).
TEST(ColorSpace, BradfordMatchesLindbloom) {
  const Mat3 expected{{{{1.0478112, 0.0228866, -0.0501270},
                        {0.0295424, 0.9904844, -0.0170491},
                        {-0.0092345, 0.0150436, 0.7521316}}}};
  const Mat3 m = bradford_adaptation({0.95047, 1.0, 1.08883}, {0.96422, 1.0, 0.82521});
  expect_matrix_near(m, expected, 1e-6);
  const Vec3 w = m * Vec3{0.95047, 1.0, 1.08883};
  EXPECT_NEAR(w.x, 0.96422, 1e-12);
  EXPECT_NEAR(w.z, 0.82521, 1e-12);
}

TEST(SrgbTransfer, HalfGreyEncodesTo188) {
  EXPECT_EQ(srgb_encode_8bit(0.5), 188);
  EXPECT_EQ(srgb_encode_8bit(0.0), 0);
  EXPECT_EQ(srgb_encode_8bit(1.0), 255);
  EXPECT_EQ(srgb_encode_8bit(7.0), 255);  // clamped
  EXPECT_EQ(srgb_encode_8bit(-1.0), 0);
  EXPECT_EQ(srgb_encode_8bit(NAN), 0);
  EXPECT_EQ(srgb_encode_8bit(0.18), 118);  // 18 % grey
}

TEST(SrgbTransfer, DecodeInvertsEncodeAndIsContinuous) {
  for (double v = 0.0; v <= 1.0; v += 0.01) EXPECT_NEAR(srgb_decode(srgb_encode(v)), v, 1e-12);
  EXPECT_NEAR(12.92 * 0.0031308, 1.055 * std::pow(0.0031308, 1 / 2.4) - 0.055, 1e-6);
}

TEST(Cielab, WhiteAndSrgbRed) {
  const Lab white = xyz_to_lab(d65_white_xyz());
  EXPECT_NEAR(white.L, 100.0, 1e-12);
  EXPECT_NEAR(white.a, 0.0, 1e-12);
  EXPECT_NEAR(white.b, 0.0, 1e-12);
  // sRGB red (1,0,0): L* 53.24, a* 80.09, b* 67.20 (standard published value).
  const Lab red = xyz_to_lab(linear_rgb_to_xyz(kRec709, {1.0, 0.0, 0.0}));
  EXPECT_NEAR(red.L, 53.24, 0.01);
  EXPECT_NEAR(red.a, 80.09, 0.01);
  EXPECT_NEAR(red.b, 67.20, 0.01);
  // Below the linear segment's knee: Y = 0.001 -> L* = 903.3 · 0.001.
  EXPECT_NEAR(xyz_to_lab(d65_white_xyz() * 0.001).L, 0.9033, 1e-4);
}

}  // namespace
}  // namespace bouguer
