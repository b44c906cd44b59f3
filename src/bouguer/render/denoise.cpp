#include "bouguer/render/denoise.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "bouguer/core/error.h"

namespace bouguer {
namespace {

// Per pixel: in the film's half buffers 4 doubles; the half images 7 doubles and a flag; the
// variance 3 floats and its scratch 4 (a value, a count, a row sum each, the mean); per offset a
// distance, a count, two row sums and the patch mean (5 floats); two weighted sums of differences
// and two weights (8 doubles); the noisy image's rgb (3 floats).
constexpr std::uint64_t kBytesPerPixel = 4 * 8 + (7 * 8 + 1) + (3 + 4) * 4 + 5 * 4 + 8 * 8 + 3 * 4;

std::size_t at(int x, int y, int width) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
}

// Rows [0, height) in parallel, each row's work its own: the result does not depend on threads.
template <class F>
void for_rows(tbb::task_arena& arena, int height, const F& f) {
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, height, 8), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y != r.end(); ++y) f(y);
    });
  });
}

// The mean of `value` over the entries with count 1 in the (2f+1)² window about each pixel (the
// window cut at the image's edges, nothing repeated); 0 where there is none. `row_value` and
// `row_count` are scratch.
struct BoxScratch {
  std::vector<float> row_value, row_count;
};
void box_mean(tbb::task_arena& arena, const std::vector<float>& value, const std::vector<float>& count,
              BoxScratch& scratch, std::vector<float>& out, int width, int height, int f) {
  for_rows(arena, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      float s = 0.0f, n = 0.0f;
      for (int d = std::max(-f, -x); d <= f && x + d < width; ++d) {
        s += value[at(x + d, y, width)];
        n += count[at(x + d, y, width)];
      }
      scratch.row_value[at(x, y, width)] = s;
      scratch.row_count[at(x, y, width)] = n;
    }
  });
  for_rows(arena, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      float s = 0.0f, n = 0.0f;
      for (int d = std::max(-f, -y); d <= f && y + d < height; ++d) {
        s += scratch.row_value[at(x, y + d, width)];
        n += scratch.row_count[at(x, y + d, width)];
      }
      out[at(x, y, width)] = n > 0.0f ? s / n : 0.0f;
    }
  });
}

}  // namespace

HalfImages half_images(const FilmBuffer& buffer, const Film& film) {
  HalfImages h;
  h.width = buffer.width();
  h.height = buffer.height();
  const std::size_t n = static_cast<std::size_t>(h.width) * static_cast<std::size_t>(h.height);
  h.a.resize(n);
  h.b.resize(n);
  h.even_share.assign(n, 0.5);
  h.usable.assign(n, 0);
  if (!buffer.keeps_halves()) return h;
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x) {
      const std::size_t p = at(x, y, h.width);
      const auto [even, odd] = buffer.half_means(x, y);
      const double total = buffer.weight_at(x, y), odd_weight = buffer.odd_weight_at(x, y);
      const double even_weight = total - odd_weight;
      // The film's value is the camera samples' mean plus the splats; the splats go to both halves.
      const Vec3f shown = film.rgb_at(x, y);
      Vec3 splats{shown.x, shown.y, shown.z};
      if (total > 0.0) splats = splats - (even * even_weight + odd * odd_weight) / total;
      h.a[p] = even + splats;
      h.b[p] = odd + splats;
      if (total > 0.0) h.even_share[p] = even_weight / total;
      h.usable[p] = even_weight > 0.0 && odd_weight > 0.0;
    }
  return h;
}

DenoiseStats denoise(Film& film, const HalfImages& halves, const DenoiseSettings& settings,
                     const std::atomic<bool>* cancel) {
  const auto start = std::chrono::steady_clock::now();
  const int width = film.width, height = film.height;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (halves.width != width || halves.height != height || halves.a.size() != n || halves.b.size() != n ||
      halves.even_share.size() != n || halves.usable.size() != n || film.rgb.size() != 3 * n)
    throw Error(fmt::format("denoise: half images of {}x{} ({} pixels) for a film of {}x{}", halves.width,
                            halves.height, halves.a.size(), width, height));
  tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency());
  BoxScratch scratch{std::vector<float>(n), std::vector<float>(n)};
  std::vector<float> usable(n);
  for (std::size_t p = 0; p < n; ++p) usable[p] = halves.usable[p] ? 1.0f : 0.0f;

  // The variance of one half's mean, per channel: Var(A − B) = 2·Var(half), so (A − B)²/2, whose
  // one degree of freedom is averaged over the usable pixels of the 3×3 about it.
  std::vector<float> variance(3 * n);
  {
    std::vector<float> single(n), smooth(n);
    for (std::size_t c = 0; c < 3; ++c) {
      for (std::size_t p = 0; p < n; ++p) {
        const double d = halves.a[p][c] - halves.b[p][c];
        single[p] = halves.usable[p] ? static_cast<float>(0.5 * d * d) : 0.0f;
      }
      box_mean(arena, single, usable, scratch, smooth, width, height, 1);
      for (std::size_t p = 0; p < n; ++p) variance[3 * p + c] = smooth[p];
    }
  }
  // The distance's floor keeps a noiseless pair's ratio finite. Relative to the image's level, so
  // that the filter does the same to an image and to the same image a million times dimmer.
  double level = 0.0;
  std::size_t counted = 0;
  for (std::size_t p = 0; p < n; ++p)
    if (halves.usable[p]) level += std::abs(halves.a[p].x + halves.a[p].y + halves.a[p].z) / 3.0, ++counted;
  if (counted > 0) level /= static_cast<double>(counted);
  const double floor = std::max(1e-10 * level * level, 1e-300);

  // For each offset (dx, dy) in the search window, the patch distance between p and q = p + (dx, dy)
  // read from one half (the paper's eq. 7: the squared difference less the variance it would show
  // by noise alone, over k² times the variance it may show), its mean over the pairs (p', q') of the
  // two patches that both lie in the image and are usable; its weight exp(−max(0, d)) multiplies
  // the other half's value at q. Each pixel sums its offsets in the same order whatever the threads.
  const int r = settings.search_radius_px, f = settings.patch_radius_px;
  const double k2 = settings.strength * settings.strength;
  constexpr double kAlpha = 1.0;  // how much of the noise's expected difference is taken off
  // Weighted sums of the other half's differences from p's own value (so that neighbours equal to p
  // leave it exactly as it was), and the weights: [0] filters half a with weights read from b,
  // [1] filters b with weights read from a.
  std::vector<Vec3> sum[2] = {std::vector<Vec3>(n), std::vector<Vec3>(n)};
  std::vector<double> weight[2] = {std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
  std::vector<float> distance(n), valid(n), patch(n);
  const std::vector<Vec3>* values[2] = {&halves.a, &halves.b};
  DenoiseStats stats;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      if (cancel && cancel->load()) {
        stats.cancelled = true;
        return stats;
      }
      for (int side = 0; side < 2; ++side) {
        const std::vector<Vec3>& guide = *values[1 - side];
        const std::vector<Vec3>& value = *values[side];
        for_rows(arena, height, [&](int y) {
          const int qy = y + dy;
          for (int x = 0; x < width; ++x) {
            const std::size_t p = at(x, y, width);
            const int qx = x + dx;
            distance[p] = 0.0f, valid[p] = 0.0f;
            if (qy < 0 || qy >= height || qx < 0 || qx >= width) continue;
            const std::size_t q = at(qx, qy, width);
            if (!halves.usable[p] || !halves.usable[q]) continue;
            double d = 0.0;
            for (std::size_t c = 0; c < 3; ++c) {
              const double vp = variance[3 * p + c], vq = variance[3 * q + c];
              const double diff = guide[p][c] - guide[q][c];
              d += (diff * diff - kAlpha * (vp + std::min(vp, vq))) / (floor + k2 * (vp + vq));
            }
            distance[p] = static_cast<float>(d / 3.0), valid[p] = 1.0f;
          }
        });
        box_mean(arena, distance, valid, scratch, patch, width, height, f);
        for_rows(arena, height, [&](int y) {
          const int qy = y + dy;
          if (qy < 0 || qy >= height) return;
          for (int x = 0; x < width; ++x) {
            const int qx = x + dx;
            if (qx < 0 || qx >= width) continue;
            const std::size_t p = at(x, y, width), q = at(qx, qy, width);
            if (!halves.usable[p] || !halves.usable[q]) continue;
            const double w = std::exp(-std::max(0.0, static_cast<double>(patch[p])));
            if (w == 0.0) continue;
            sum[side][p] = sum[side][p] + (value[q] - value[p]) * w;
            weight[side][p] += w;
          }
        });
      }
    }

  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t p = at(x, y, width);
      if (!halves.usable[p]) {
        ++stats.pixels_left;
        continue;
      }
      // The film's value moved by each half's filtered difference, weighted as the film weighs the
      // halves (the centre weighs exp(0) = 1 in both sums: its distance to itself is at most zero).
      const double share = halves.even_share[p];
      const Vec3 change = sum[0][p] / weight[0][p] * share + sum[1][p] / weight[1][p] * (1.0 - share);
      const Vec3f shown = film.rgb_at(x, y);
      film.set_rgb(x, y, {static_cast<float>(shown.x + change.x), static_cast<float>(shown.y + change.y),
                          static_cast<float>(shown.z + change.z)});
    }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

void check_denoisable(IntegratorType type, std::string_view option) {
  if (type == IntegratorType::light)
    fail_usage("{}: the light tracer's image is all light-path splats, whose noise the half buffers do not see; use "
               "path, bdpt or vcm",
               option);
}

std::uint64_t denoise_bytes_needed(int width_px, int height_px) {
  return static_cast<std::uint64_t>(width_px) * static_cast<std::uint64_t>(height_px) * kBytesPerPixel;
}

}  // namespace bouguer
