#include "bouguer/render/adaptive.h"

#include <algorithm>

#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

Lab lab_of(const Vec3& rgb, const DisplayTransform& d) {
  Vec3 v = rgb;
  if (d.balanced) v = d.white_balance * v;
  v = v * d.scale;
  return xyz_to_lab(linear_rgb_to_xyz(kRec709, {std::max(0.0, v.x), std::max(0.0, v.y), std::max(0.0, v.z)}));
}

}  // namespace

double pixel_error_de00(const FilmBuffer& film, int x, int y, const DisplayTransform& display) {
  const auto [even, odd] = film.half_means(x, y);
  return 0.5 * ciede2000(lab_of(even, display), lab_of(odd, display));
}

std::size_t retire_converged(const FilmBuffer& film, const NoiseTarget& target, int samples_done,
                             std::vector<std::uint8_t>& active) {
  std::size_t left = 0;
  for (int y = 0; y < film.height(); ++y)
    for (int x = 0; x < film.width(); ++x) {
      std::uint8_t& flag = active[static_cast<std::size_t>(y) * static_cast<std::size_t>(film.width()) +
                                  static_cast<std::size_t>(x)];
      if (!flag) continue;
      if (samples_done >= target.min_spp && pixel_error_de00(film, x, y, target.display) <= target.delta_e00)
        flag = 0;
      else
        ++left;
    }
  return left;
}

Film samples_map(const FilmBuffer& film) {
  Film map(film.width(), film.height());
  for (int y = 0; y < film.height(); ++y)
    for (int x = 0; x < film.width(); ++x) {
      const auto n = static_cast<float>(film.weight_at(x, y));
      map.set_rgb(x, y, {n, n, n});
    }
  return map;
}

}  // namespace bouguer
