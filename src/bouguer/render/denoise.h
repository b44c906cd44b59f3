#pragma once
// Denoising a render from its two half buffers (--denoise; #37): non-local means with the two
// halves filtering each other (Rousselle, Knaus, Zwicker 2012, "Adaptive rendering with non-local
// means filtering"; the dual-buffer form of Rousselle, Manzi, Zwicker 2013, as Cycles' first
// denoiser had it). The film keeps its odd-numbered camera samples apart (FilmBuffer::keep_halves),
// so every pixel has two independent estimates A and B of the same value. Each is filtered with
// weights read from the other, so that a weight is independent of the value it multiplies (the
// paper's reason; on the tests' heavy-tailed noise, self-weighting measured no worse). The pixel's
// variance comes from (A − B)², so the filter knows the noise it is averaging: where the halves
// agree throughout a neighbourhood (a converged region, a noiseless image) it is left as it was.
// A post-process on the linear film: deterministic, independent of threads and passes; biased
// (it averages neighbours alike within their noise), consistent (the weights close as the noise
// falls). Only the linear Rec.709 image is filtered; the spectral film is left as rendered.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "bouguer/io/image.h"
#include "bouguer/render/film.h"
#include "bouguer/scene/description.h"

namespace bouguer {

struct DenoiseSettings {
  int search_radius_px = 7;  // neighbours q within a (2r+1)² window of p
  int patch_radius_px = 3;   // patches of (2f+1)² pixels about p and q compared
  // k: a patch counts as alike while its pixels differ by about k times their combined standard
  // deviation; larger filters more (the paper's 0.45).
  double strength = 0.45;
  int threads = 0;  // 0: all cores (the result does not depend on it)
};

// A film's two half images: the means of its even- and odd-numbered camera samples per pixel
// (linear Rec.709), with the film's splats (light paths, which are not kept in halves) added to
// both, and the even half's share of the pixel's samples, so that share·a + (1 − share)·b is the
// film's own image. `usable` is 0 where a half has no sample: that pixel is left as rendered, and
// it enters neither its neighbours' means, nor their patch distances, nor their variance.
struct HalfImages {
  int width = 0, height = 0;
  std::vector<Vec3> a, b;
  std::vector<double> even_share;
  std::vector<std::uint8_t> usable;
};
HalfImages half_images(const FilmBuffer& buffer, const Film& film);

// What one denoising did, for --stats-json.
struct DenoiseStats {
  double seconds = 0.0;
  std::size_t pixels_left = 0;  // pixels left as rendered (a half with no sample)
  bool cancelled = false;       // `cancel` was raised: the film is as it came
};

// Refuses (a usage error naming `option`) an estimator whose image the half buffers cannot tell
// the noise of: the light tracer's, all light-path splats.
void check_denoisable(IntegratorType type, std::string_view option);

// The memory denoising takes for a film of this size beyond the film itself: the film's half
// buffers, the half images, the filter's arrays and a copy of the noisy image's rgb; make_film
// checks it with the film's own (render/render.h).
std::uint64_t denoise_bytes_needed(int width_px, int height_px);

// Replaces film.rgb by the denoised image of `halves` (same size as the film); the spectra stay.
// Each pixel is its own value plus the weighted mean of its alike neighbours' differences from it,
// so a pixel with none (a converged neighbourhood, an unlike one) is exactly what it was.
// `cancel` (may be null) is read between the search window's offsets: once it is set the film is
// left as it came and `cancelled` is set.
DenoiseStats denoise(Film& film, const HalfImages& halves, const DenoiseSettings& settings,
                     const std::atomic<bool>* cancel = nullptr);

}  // namespace bouguer
