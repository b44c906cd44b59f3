#pragma once
// What a camera does between the linear film and the file a person looks at (docs/colour.md,
// "Exposure and display"): white balance (Bradford adaptation of a source white to the display's
// D65), exposure (a compensation in EV on top of an absolute camera exposure from ISO, shutter
// time and f-number, or of an automatic one measured on the finished film), and the display curve
// of PNG and the report (clip, or a filmic shoulder that keeps hue). The film stays linear: these
// apply to a copy as an image is written, and EXR, PFM and the spectral EXR get the exposure and
// the white balance only when asked (`float_outputs`), never the curve.
//
//   DisplayDesc (the scene's "display" block, the command line) ──resolve_display(film)──▶
//   DisplayTransform (a scale, a 3×3 matrix, a curve) ──displayed / exposed──▶ the written Film
#include <optional>
#include <span>
#include <string>
#include <variant>

#include "bouguer/core/math.h"
#include "bouguer/io/image.h"

namespace bouguer {

enum class DisplayCurve { clip, filmic };

// An absolute exposure as a camera sets it (saturation-based sensitivity, ISO 12232).
struct CameraExposure {
  double iso = 100.0;       // S
  double shutter_s = 0.01;  // t
  double f_number = 1.0;    // N
};

// White balance: none, to a named illuminant's white (its CIE 1931 XYZ at Y = 1), or to the
// scene's brightest emitter (found by scene/display_white.h once the scene is compiled).
struct NoWhiteBalance {};
struct IlluminantWhite {
  std::string name;
  Vec3 white_xyz;
};
struct BrightestEmitterWhite {};
using WhiteBalance = std::variant<NoWhiteBalance, IlluminantWhite, BrightestEmitterWhite>;

// The description's values: everything off (the film written as it is) by default.
struct DisplayDesc {
  double exposure_ev = 0.0;              // compensation: linear values ×2^ev, on top of the rest
  std::optional<CameraExposure> camera;  // absolute exposure; then no automatic one
  bool auto_exposure = false;            // on by default for assets in photometric units
  WhiteBalance white_balance = NoWhiteBalance{};
  DisplayCurve curve = DisplayCurve::clip;
  bool float_outputs = false;  // EXR, PFM, spectral EXR exposed and balanced too
};

// What is applied to each pixel: rgb' = curve(scale · M · rgb), linear Rec.709 in and out.
struct DisplayTransform {
  double scale = 1.0;
  Mat3 white_balance = Mat3::identity();
  bool balanced = false;  // white_balance is not the identity
  DisplayCurve curve = DisplayCurve::clip;
  bool float_outputs = false;

  // Nothing to do for PNG (and, below, for the float formats): the film is written bit for bit.
  bool leaves_png() const { return scale == 1.0 && !balanced && curve == DisplayCurve::clip; }
  bool leaves_floats() const { return !float_outputs || (scale == 1.0 && !balanced); }
};

// ---- the pure functions (each with its closed-form test) ---------------------------------------

// EV100 = log2(N²/t) − log2(S/100) (Lagarde & de Rousiers 2014, eq. 19).
double ev100(const CameraExposure& c);
// The factor from luminance (cd/m²) to display values, 1/(1.2·2^EV100) = t·S/(120·N²): the
// luminance that saturates the sensor, L_max = (78/(0.65·S))·N²/t (ISO 12232's saturation-based
// speed with a lens transmittance and vignetting q = 0.65), is display white 1.
double camera_exposure_scale(const CameraExposure& c);
// ×2^ev: +1 EV doubles the linear values.
double compensation_scale(double ev);

// The automatic exposure of a film's linear rgb (as the white balance `m` makes it): the factor
// that puts the kAutoPercentile-th percentile of the largest channel, max(R, G, B), of the pixels
// that are not black at kAutoTarget, so that the lit surfaces are bright and the brightest of them below white (up
// to 1/0.8 = 1.25 times that percentile), while the few brightest pixels (highlights, noise, a
// lamp seen directly) may clip. 1 for a black film. Why this statistic: docs/colour.md.
inline constexpr double kAutoPercentile = 0.97, kAutoTarget = 0.8;
double auto_exposure_scale(std::span<const float> rgb, const Mat3& m = Mat3::identity());

// The matrix on linear Rec.709 that adapts colours seen under `source_white_xyz` to D65 (the
// display's white, RGB (1, 1, 1)): XYZ→RGB · Bradford(source → D65) · RGB→XYZ. The source white
// (any luminance) becomes a neutral of the same luminance.
Mat3 white_balance_matrix(const Vec3& source_white_xyz);

// The filmic shoulder on one value: x below kFilmicKnee unchanged, above it
// k + (1 − k)·(1 − exp(−(x − k)/(1 − k))): continuous with its slope at the knee, increasing,
// approaching 1 (below it for every x; in double precision it reaches 1 near x = 15). 0 maps to 0.
inline constexpr double kFilmicKnee = 0.6;
double filmic_shoulder(double x);
// The curve on a colour, keeping its hue: all three channels scaled by shoulder(m)/m, m = max(r, g, b),
// so the largest channel ends at most 1 and no channel clips.
Vec3 filmic(const Vec3& rgb);

// ---- applying it --------------------------------------------------------------------------------

// The transform of a film: exposure from the description (camera, automatic and compensation
// multiply), white balance from the description or, for BrightestEmitterWhite, `emitter_white_xyz`
// (none: no balance). Deterministic: a function of the film's values only.
DisplayTransform resolve_display(const DisplayDesc& d, const Film& film,
                                 const std::optional<Vec3>& emitter_white_xyz = std::nullopt);

// The film as PNG and the report show it: balanced, exposed and through the curve (then clamped
// to [0, 1] by the PNG encoder). Spectra are dropped.
Film displayed(const Film& film, const DisplayTransform& t);
// The film as the float formats get it: balanced and exposed when t.float_outputs (spectra
// scaled by the exposure alone: a chromatic adaptation has no meaning per wavelength), else as it is.
Film exposed(const Film& film, const DisplayTransform& t);

}  // namespace bouguer
