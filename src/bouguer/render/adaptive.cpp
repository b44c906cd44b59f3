#include "bouguer/render/adaptive.h"

#include "bouguer/render/compare.h"

namespace bouguer {
namespace {

// A linear colour as the display shows it, before its curve: white-balanced and exposed.
Vec3 displayed(const Vec3& rgb, const DisplayTransform& d) { return (d.balanced ? d.white_balance * rgb : rgb) * d.scale; }

}  // namespace

double halves_error_de00(const Vec3& a, const Vec3& b, const DisplayTransform& display) {
  return 0.5 * delta_e00(displayed(a, display), displayed(b, display));
}

double pixel_error_de00(const FilmBuffer& film, int x, int y, const DisplayTransform& display) {
  const auto [even, odd] = film.half_means(x, y);
  return halves_error_de00(even, odd, display);
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
