#pragma once
// Colour difference between two images of linear Rec.709: per-pixel CIEDE2000 with CIELAB
// relative to D65 at Y = 1 (a D65 emitter of scale 1 is L* = 100), and summary statistics.
#include <vector>

#include "bouguer/render/film.h"

namespace bouguer {

struct ImageDifference {
  int width = 0, height = 0;
  std::vector<double> delta_e;  // per pixel, row-major from the top
  double mean = 0, median = 0, p95 = 0, max = 0;
  double rmse = 0;  // root mean square difference of the linear RGB values, all pixels and channels
  // Which of the two a difference is, lightness or colour: the mean CIEDE2000 with only L* taken
  // from B (A's a*, b*), and with only a*, b* taken from B (A's L*). Per pixel the two add in
  // quadrature to the whole (CIEDE2000's lightness term stands apart from its chroma and hue
  // terms); their means do not add up to `mean`. Near white, CIEDE2000 weighs a colour difference
  // more than a lightness one (S_L grows with |L* − 50|, S_C only with chroma), so a spectral
  // render's noise there is mostly colour.
  double mean_lightness = 0, mean_colour = 0;
};

ImageDifference compare_images(const Film& a, const Film& b);

// CIEDE2000 between two linear Rec.709 colours (negative channels read as 0), as compare_images
// takes it per pixel.
double delta_e00(const Vec3& a, const Vec3& b);

// ΔE00 from 0 (black) through blue, green, yellow, red to white at `max_delta_e` and above.
Film delta_e_heatmap(const ImageDifference& d, double max_delta_e);

// Images of equal height placed left to right with `gap_px` white columns between them.
Film side_by_side(const std::vector<const Film*>& images, int gap_px);

}  // namespace bouguer
