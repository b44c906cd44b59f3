#pragma once
// CIELAB (CIE 015) and the CIEDE2000 colour difference (Sharma, Wu, Dalal 2005).
#include "bouguer/core/math.h"

namespace bouguer {

struct Lab {
  double L = 0.0, a = 0.0, b = 0.0;
};

// White of the CIELAB conversions: D65 at xy (0.3127, 0.3290) with Y normalised to 1.
Vec3 d65_white_xyz();

Lab xyz_to_lab(const Vec3& xyz, const Vec3& white_xyz = d65_white_xyz());

// CIEDE2000 with parametric factors kL = kC = kH = 1.
double ciede2000(const Lab& lab1, const Lab& lab2);

}  // namespace bouguer
