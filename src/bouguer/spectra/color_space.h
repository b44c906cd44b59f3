#pragma once
// RGB colour spaces defined by primaries and white point (CIE 1931 xy), the matrices between them
// and XYZ, Bradford chromatic adaptation, and the sRGB transfer curve.
// Convention: XYZ coming from the renderer is relative to a D65-lit scene (the film is linear
// Rec.709 with D65 white). Converting to a space with another white (ACEScg) applies Bradford
// adaptation from D65 to that white, as colour-managed pipelines (OCIO/ACES) do.
#include <string>
#include <string_view>

#include "bouguer/core/math.h"

namespace bouguer {

struct Chromaticity {
  double x = 0.0, y = 0.0;
};

struct ColorSpace {
  std::string_view name;
  Chromaticity red, green, blue, white;
};

inline constexpr Chromaticity kD65White{0.3127, 0.3290};   // ITU-R BT.709 / IEC 61966-2-1
inline constexpr Chromaticity kAcesWhite{0.32168, 0.33767};  // SMPTE ST 2065-1

inline constexpr ColorSpace kRec709{"linear sRGB (Rec.709)", {0.640, 0.330}, {0.300, 0.600}, {0.150, 0.060}, kD65White};
inline constexpr ColorSpace kRec2020{"Rec.2020", {0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046}, kD65White};
inline constexpr ColorSpace kAcesCg{"ACEScg (AP1)", {0.713, 0.293}, {0.165, 0.830}, {0.128, 0.044}, kAcesWhite};

// Luminance Y of linear Rec.709 (the Y row of its RGB-to-XYZ matrix, as ITU-R BT.709 rounds it):
// the one weighting of the film's colours by brightness (lamp power, texture means, blocks of pixels).
constexpr double rec709_luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// Linear RGB (white = (1,1,1) at Y = 1) to XYZ, and back.
Mat3 rgb_to_xyz_matrix(const ColorSpace& cs);
Mat3 xyz_to_rgb_matrix(const ColorSpace& cs);

// Bradford transform taking colours seen under source_white to corresponding colours under
// target_white (both XYZ).
Mat3 bradford_adaptation(const Vec3& source_white_xyz, const Vec3& target_white_xyz);

// XYZ of a D65-referenced scene into linear RGB of `cs`, adapting the white when `cs` is not D65.
Vec3 xyz_to_linear_rgb(const ColorSpace& cs, const Vec3& xyz);
Vec3 linear_rgb_to_xyz(const ColorSpace& cs, const Vec3& rgb);

// The sRGB transfer curve (IEC 61966-2-1): linear light <-> encoded value, both in [0, 1] for in-range input.
double srgb_encode(double linear);
double srgb_decode(double encoded);

// 8-bit sRGB code value of a linear value: clamped to [0, 1], encoded, rounded.
unsigned char srgb_encode_8bit(double linear);

// "#RRGGBB" of a linear Rec.709 colour, each channel as srgb_encode_8bit.
std::string srgb_hex(const Vec3& linear_rec709);

}  // namespace bouguer
