#pragma once
// Adaptive sampling to a noise target (#37; Cycles' adaptive sampling): each pixel's error is
// estimated from its two independent halves (the film keeps its odd-numbered samples apart:
// FilmBuffer::keep_halves), and a pixel whose estimate is at or below the target takes no more
// samples. Decided only between passes, from the samples those passes gave, so the same seed
// gives the same image at any thread count. Only for estimators whose samples stay in their pixel
// (no splats: a pixel that stopped would change the light its light paths splat elsewhere).
#include <cstdint>
#include <vector>

#include "bouguer/io/display.h"
#include "bouguer/render/film.h"

namespace bouguer {

// The target and when it may be read.
struct NoiseTarget {
  double delta_e00 = 0.0;  // the error allowed per pixel, CIEDE2000 on the display colour
  int min_spp = 16;        // no pixel stops with fewer samples: a small sample's halves can agree by chance
  // The display's exposure and white balance (io/display.h; the curve is left out: it would hide
  // the noise of what it clips), as resolved on the film so far.
  DisplayTransform display;
};

// A pixel's error estimate: with A and B its halves' means (linear Rec.709, white-balanced and
// exposed as the display will show them),
// the mean (A + B)/2 is off from the truth by about |A − B|/2 per channel (A − B has twice the
// variance of each half, four times the mean's), so ΔE00(A, B)/2 with CIELAB relative to D65 at
// Y = 1 (compare.h: white is L* = 100). Zero-sample halves read as black.
double pixel_error_de00(const FilmBuffer& film, int x, int y, const DisplayTransform& display);
// The same from the two halves' means (linear Rec.709, before the display's transform).
double halves_error_de00(const Vec3& a, const Vec3& b, const DisplayTransform& display);

// After a pass that left `samples_done` samples in every active pixel: clears the flag of each
// active pixel whose estimate is at or below the target (once samples_done ≥ min_spp). Returns the
// pixels still active.
std::size_t retire_converged(const FilmBuffer& film, const NoiseTarget& target, int samples_done,
                             std::vector<std::uint8_t>& active);

// The samples each pixel took (an image for --spp-map: every channel the count).
Film samples_map(const FilmBuffer& film);

}  // namespace bouguer
