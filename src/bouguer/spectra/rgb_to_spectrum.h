#pragma once
// RGB colours lifted to smooth spectra (Jakob & Hanika 2019): a reflectance is
// S(c0 λ² + c1 λ + c2) with the sigmoid S(x) = 1/2 + x / (2 √(1 + x²)), fitted so that its colour
// under D65 (CIE 1931) is the given linear Rec.709 colour; an emitter's RGB radiance is
// scale · S(poly(λ)) · D65(λ), D65 normalised to luminance 1, with scale = 2·max(r, g, b) so the
// sigmoid works around 1/2, away from its flat ends (as pbrt-v4 does). RGB (1, 1, 1) is thus D65 at
// Y = 1, the renderer's white.
#include "bouguer/core/math.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

// Reflectance spectrum of a linear Rec.709 colour; components are clamped to [0, 1].
SigmoidPolynomial rgb_to_reflectance(const Vec3& linear_rec709);

// Emission spectrum of a linear Rec.709 radiance (components clamped at 0).
RgbIlluminantSpectrum rgb_to_illuminant(const Vec3& linear_rec709);

}  // namespace bouguer
