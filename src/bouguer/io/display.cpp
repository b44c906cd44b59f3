#include "bouguer/io/display.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {

double ev100(const CameraExposure& c) {
  return std::log2(c.f_number * c.f_number / c.shutter_s) - std::log2(c.iso / 100.0);
}

double camera_exposure_scale(const CameraExposure& c) { return 1.0 / (1.2 * std::exp2(ev100(c))); }

double compensation_scale(double ev) { return std::exp2(ev); }

double auto_exposure_scale(std::span<const float> rgb, const Mat3& m) {
  // The largest channel after the white balance, not the luminance: a lit red floor metered by its
  // luminance (a quarter of its red) would clip in red; for a neutral pixel the two are the same.
  std::vector<double> lit;
  lit.reserve(rgb.size() / 3);
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3) {
    const Vec3 v = m * Vec3{rgb[i], rgb[i + 1], rgb[i + 2]};
    const double peak = std::max({v.x, v.y, v.z});
    if (peak > 0.0) lit.push_back(peak);
  }
  if (lit.empty()) return 1.0;
  // The nearest-rank percentile: the smallest value with at least that fraction of the lit pixels at or below it.
  const auto rank = static_cast<std::size_t>(std::ceil(kAutoPercentile * static_cast<double>(lit.size())));
  const auto at = lit.begin() + static_cast<std::ptrdiff_t>(std::clamp<std::size_t>(rank, 1, lit.size()) - 1);
  std::nth_element(lit.begin(), at, lit.end());
  return kAutoTarget / *at;
}

Mat3 white_balance_matrix(const Vec3& source_white_xyz) {
  const Vec3 d65 = xy_to_xyz(kD65White.x, kD65White.y, source_white_xyz.y);
  return xyz_to_rgb_matrix(kRec709) * bradford_adaptation(source_white_xyz, d65) * rgb_to_xyz_matrix(kRec709);
}

double filmic_shoulder(double x) {
  constexpr double k = kFilmicKnee;
  if (x <= k) return x;
  return k + (1.0 - k) * -std::expm1(-(x - k) / (1.0 - k));
}

Vec3 filmic(const Vec3& rgb) {
  const double m = std::max({rgb.x, rgb.y, rgb.z});
  if (!(m > kFilmicKnee)) return rgb;  // below the knee the curve is the identity
  return rgb * (filmic_shoulder(m) / m);
}

DisplayTransform resolve_display(const DisplayDesc& d, const Film& film, const std::optional<Vec3>& emitter_white_xyz) {
  DisplayTransform t;
  t.curve = d.curve;
  t.float_outputs = d.float_outputs;
  std::optional<Vec3> white;
  if (const auto* named = std::get_if<IlluminantWhite>(&d.white_balance))
    white = named->white_xyz;
  else if (std::holds_alternative<BrightestEmitterWhite>(d.white_balance))
    white = emitter_white_xyz;
  if (white && white->y > 0.0) {
    t.white_balance = white_balance_matrix(*white);
    t.balanced = true;
  }
  if (d.camera)
    t.scale = camera_exposure_scale(*d.camera);
  else if (d.auto_exposure)
    t.scale = auto_exposure_scale(film.rgb, t.white_balance);
  t.scale *= compensation_scale(d.exposure_ev);
  return t;
}

namespace {

Vec3f balanced_and_exposed(const Vec3f& rgb, const DisplayTransform& t) {
  Vec3 v{rgb.x, rgb.y, rgb.z};
  if (t.balanced) v = t.white_balance * v;
  v = v * t.scale;
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

}  // namespace

Film displayed(const Film& film, const DisplayTransform& t) {
  Film out(film.width, film.height);
  if (t.leaves_png()) {
    out.rgb = film.rgb;
    return out;
  }
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      Vec3f v = balanced_and_exposed(film.rgb_at(x, y), t);
      if (t.curve == DisplayCurve::filmic) {
        const Vec3 f = filmic(Vec3{v.x, v.y, v.z});
        v = {static_cast<float>(f.x), static_cast<float>(f.y), static_cast<float>(f.z)};
      }
      out.set_rgb(x, y, v);
    }
  return out;
}

Film exposed(const Film& film, const DisplayTransform& t) {
  if (t.leaves_floats()) return film;
  Film out = film;
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) out.set_rgb(x, y, balanced_and_exposed(film.rgb_at(x, y), t));
  for (float& s : out.spectral) s = static_cast<float>(s * t.scale);
  return out;
}

}  // namespace bouguer
