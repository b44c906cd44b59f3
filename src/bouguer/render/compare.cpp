#include "bouguer/render/compare.h"

#include <algorithm>
#include <cmath>

#include "bouguer/core/error.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(std::clamp(p * static_cast<double>(v.size() - 1), 0.0, double(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

Lab lab_of(const Vec3& rgb) {
  return xyz_to_lab(linear_rgb_to_xyz(kRec709, {std::max(0.0, rgb.x), std::max(0.0, rgb.y), std::max(0.0, rgb.z)}));
}

}  // namespace

double delta_e00(const Vec3& a, const Vec3& b) { return ciede2000(lab_of(a), lab_of(b)); }

ImageDifference compare_images(const Film& a, const Film& b) {
  if (a.width != b.width || a.height != b.height)
    fail("images differ in size ({}x{} and {}x{})", a.width, a.height, b.width, b.height);
  ImageDifference d;
  d.width = a.width;
  d.height = a.height;
  double sum = 0.0, squared = 0.0, lightness = 0.0, colour = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const Vec3f pa = a.rgb_at(x, y), pb = b.rgb_at(x, y);
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(pa[c]) || !std::isfinite(pb[c]))
          fail("pixel ({}, {}) of the {} image is not finite ({}): a difference needs finite images", x, y,
               std::isfinite(pa[c]) ? "second" : "first", std::isfinite(pa[c]) ? pb[c] : pa[c]);
      const Lab la = lab_of(Vec3{pa.x, pa.y, pa.z}), lb = lab_of(Vec3{pb.x, pb.y, pb.z});
      const double e = ciede2000(la, lb);
      if (!std::isfinite(e)) fail("pixel ({}, {}): the colour difference is not finite", x, y);
      d.delta_e.push_back(e);
      sum += e;
      lightness += ciede2000(la, Lab{lb.L, la.a, la.b});
      colour += ciede2000(la, Lab{la.L, lb.a, lb.b});
      d.max = std::max(d.max, e);
      for (int c = 0; c < 3; ++c) {
        const double diff = double(pa[c]) - double(pb[c]);  // in float, 3e38 squared would overflow
        squared += diff * diff;
      }
    }
  const auto n = static_cast<double>(d.delta_e.size());
  d.mean = n > 0 ? sum / n : 0.0;
  d.mean_lightness = n > 0 ? lightness / n : 0.0;
  d.mean_colour = n > 0 ? colour / n : 0.0;
  d.median = percentile(d.delta_e, 0.5);
  d.p95 = percentile(d.delta_e, 0.95);
  d.rmse = n > 0 ? std::sqrt(squared / (3.0 * n)) : 0.0;
  if (!std::isfinite(d.rmse)) fail("the RMS difference is not finite: the images hold values near the float limit");
  return d;
}

Film delta_e_heatmap(const ImageDifference& d, double max_delta_e) {
  static const Vec3f ramp[] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {1, 1, 1}};
  Film film(d.width, d.height);
  for (int y = 0; y < d.height; ++y)
    for (int x = 0; x < d.width; ++x) {
      const double t = std::clamp(d.delta_e[film.pixel_index(x, y)] / max_delta_e, 0.0, 1.0) * 5.0;
      const int i = std::min(static_cast<int>(t), 4);
      const float f = static_cast<float>(t - i);
      const Vec3f c = ramp[i] * (1.0f - f) + ramp[i + 1] * f;
      // Linear values whose sRGB encoding is the ramp colour.
      film.set_rgb(x, y, {float(srgb_decode(c.x)), float(srgb_decode(c.y)), float(srgb_decode(c.z))});
    }
  return film;
}

Film side_by_side(const std::vector<const Film*>& images, int gap_px) {
  int width = 0;
  for (const Film* f : images) width += f->width;
  width += gap_px * static_cast<int>(images.size() - 1);
  Film out(width, images.front()->height);
  std::fill(out.rgb.begin(), out.rgb.end(), 1.0f);
  int x0 = 0;
  for (const Film* f : images) {
    if (f->height != out.height) fail("side by side: images differ in height ({} and {})", f->height, out.height);
    for (int y = 0; y < f->height; ++y)
      for (int x = 0; x < f->width; ++x) out.set_rgb(x0 + x, y, f->rgb_at(x, y));
    x0 += f->width + gap_px;
  }
  return out;
}

}  // namespace bouguer
