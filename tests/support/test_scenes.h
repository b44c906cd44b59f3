#pragma once
// Scenes shared by several tests (as scene-file text), and estimates over pixels.
#include <cstdint>
#include <span>
#include <string>

#include "bouguer/render/film.h"

namespace bouguer::test {

// A floor, a dispersive glass sphere (dense flint), a red glass block and a small lamp: every
// event of every estimator (refraction with dispersion, absorption, diffuse, NEE, splats).
std::string busy_scene(const char* integrator, const char* spectral, int spp);

// A closed room of diffuse walls (two coloured) with a box and a ceiling lamp.
std::string room_scene(const char* integrator, int spp, std::uint64_t seed);

// A sphere of red glass over a white floor under a small lamp: the caustic. Only pixels whose
// whole footprint sees the floor directly are compared (the light tracer cannot see the floor
// through the glass).
std::string caustic_scene(const char* integrator, int spp, std::uint64_t seed);

// A glass tumbler of a dilute scattering liquid on a dark floor, lit only by a point light and a
// spot (16 × 16, hero): light reaches the liquid only through the glass (light subpaths, or the
// path tracer's connections through the walls). The scene is tests/data/lit_tumbler/scene.json
// (bench/hard_scenes.py renders it too) with `integrator` set.
std::string lit_tumbler(const char* integrator);

// tests/data/red_ball_lamp (a 20 mm red glass ball under a 5 mm spherical lamp) with the lamp moved
// to the side (at (−100, 60, −50) mm) so that the caustic and the shadow fall on the floor beside
// the ball, seen from straight above (48 × 48, 2.2 mm a pixel at the floor), with no sky: all the
// light is the lamp's, through the glass or not. `integrator` set, max_depth 8.
std::string red_ball_from_above(const char* integrator);

extern const char* const kChromaticSigmaS;  // a strongly chromatic σ_s: blue scatters 5× as much as red

// White furnace: a medium that scatters without absorbing (albedo 1, chromatic σ_s, HG g = 0.7)
// inside a lossless dielectric sphere (n = 1.33) under a uniform white background. Light is only
// redistributed, so every pixel, the sphere's included, has the background's radiance: D65 at
// Y = 1 is linear sRGB (1, 1, 1). The camera sees only the middle of the sphere (optical radius
// 1.8 in blue, 0.36 in red). The spectral MIS weights spread a path's contribution over the
// channels (about ±90 % a sample), so 8 × 8 pixels × 8192 samples are needed for 3 standard errors
// to fit in the 0.5 % tolerance.
std::string furnace_scene(const std::string& density, const char* integrator);

// A furnace ball (albedo 1, index `ior`, the path tracer, max_depth 1000) seen through its middle
// from camera_z metres away: σ_s from 400 to 700 nm (per metre, a JSON pair), HG g, radius.
std::string ball_furnace(double camera_z, const char* sigma_s_per_m, double g, const char* radius, double ior = 1.33);

struct Estimate {
  double mean = 0.0, standard_error = 0.0;
};
// Mean and standard error of one channel over pixels (the pixels are independent estimates).
// The tests require the tolerance to be at least 3 standard errors, so each can fail.
Estimate channel_estimate(const Film& f, int channel, int x0, int y0, int x1, int y1);
// The mean over the image of the pixel differences b − a in one channel, and its standard error:
// where both estimate the same image, every pixel's difference has mean 0 and the pixels are
// independent.
Estimate difference_estimate(const Film& a, const Film& b, int channel);
// Mean and standard error of independent values (the image means of several seeds).
Estimate mean_estimate(std::span<const double> values);
// One channel's mean over pixels [x0, x1) × [y0, y1), averaged over renders of independent seeds,
// and its standard error from their spread (K − 1 degrees of freedom). For an estimator whose
// pixels share random numbers, vcm's (every pixel of an iteration merges the same photons and, in
// hero mode, shares its wavelengths), one image's pixels understate the error; the seeds do not.
Estimate seeds_estimate(std::span<const Film> films, int channel, int x0, int y0, int x1, int y1);

}  // namespace bouguer::test
