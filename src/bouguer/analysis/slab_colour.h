#pragma once
// The colour of thickness: what a slab of an absorbing material looks like against a light, and
// how wrong the two RGB shortcuts are (the question behind the paper's Figs. 1, 2 and 7).
//
// A slab of thickness d and index n in air, seen at normal incidence against the illuminant,
// transmits per wavelength T(λ) = (1 − R)² τ / (1 − R² τ²) with τ = exp(−σ_a(λ) d) and
// R = ((n − 1)/(n + 1))², both surfaces and their multiple reflections included — the same slab
// as the renderer's closed-form test. Colours are XYZ of illuminant × T under the CIE 1931
// observer with the illuminant normalised to Y = 1, then linear Rec.709 and sRGB hex.
//
// The two shortcuts:
//   rgb3   — the paper's RGB tracer: σ_a sampled at 700.0, 546.1 and 435.8 nm and applied to the
//            illuminant's R, G, B;
//   fitted — an RGB renderer whose per-channel absorption was fitted so that the slab has exactly
//            the right colour at one reference thickness; away from it, it drifts.
// ΔE00 is computed in CIELAB with the illuminant as white.
#include <string>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct SlabColour {
  Vec3 xyz;
  Vec3 linear_srgb;  // Rec.709, may leave [0, 1] for saturated colours
  std::string hex;   // sRGB, clamped
};

struct ThicknessRow {
  double thickness_m = 0.0;
  std::vector<double> internal_transmittance;  // τ at ThicknessAnalysis::probe_nm
  SlabColour spectral, rgb3, fitted;
  double delta_e_rgb3 = 0.0, delta_e_fitted = 0.0;
};

struct ThicknessAnalysis {
  std::vector<double> probe_nm;
  double reference_thickness_m = 0.0;
  double ior = 1.0;                 // of the slab, in air
  double reflectance = 0.0;         // R of one surface, from ior
  Vec3 rgb3_sigma_a_per_m;          // σ_a at 700.0, 546.1, 435.8 nm
  Vec3 fitted_sigma_a_per_m;        // the fitted renderer's per-channel σ_a
  Vec3 illuminant_linear_srgb;
  std::vector<ThicknessRow> rows;
};

ThicknessAnalysis analyse_thicknesses(const Spectrum& sigma_a_per_m, double ior,
                                      const std::vector<double>& thicknesses_m, const Spectrum& illuminant,
                                      double reference_thickness_m,
                                      std::vector<double> probe_nm = {450.0, 550.0, 650.0});

// Slab transmittance (surfaces included) at one wavelength.
double slab_transmittance(double sigma_a_per_m, double thickness_m, double surface_reflectance);

// Seven thicknesses from pale to deep: factors of two from 1/8 to 8 around 1 / (mean σ_a over
// 400–700 nm), rounded to two significant digits. What `bouguer material` and the report show.
std::vector<double> default_thickness_series(const Spectrum& sigma_a_per_m);

// "250 µm", "2 mm", "1.6 cm", "27 m" (ascii "um" with ascii_only).
std::string format_thickness(double thickness_m, bool ascii_only = false);

}  // namespace bouguer
