#pragma once
// The milk model of Frisvad, Christensen & Jensen (2007), "Computing the scattering properties of
// participating media using Lorenz-Mie theory", ACM TOG 26(3), article 60: milk as water (with
// riboflavin) holding fat globules and casein micelles, each a log-normal volume distribution of
// spheres, their bulk coefficients by Lorenz-Mie theory (media/mie.h). Inputs as the model's
// authors tabulate them (data/scattering/milk-inputs.csv); constants below, each with its source.
#include "bouguer/media/mie.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct MilkComposition {
  double fat_wt_percent = 3.5;
  double protein_wt_percent = 3.4;
  double homogenization_pressure_mpa = 20.0;  // 0: not homogenised
};

// The fat globules' volume-to-surface mean radius and its standard deviation (µm), from the fat
// content and homogenisation pressure: the authors' fits to Walstra's data, with a coefficient of
// variation of 0.6.
struct FatGlobuleSize {
  double r_vs_um = 0.0, c_s_um = 0.0;
};
FatGlobuleSize fat_globule_size(const MilkComposition& milk);

// Quadrature pieces per particle population (Simpson in ln r); doubling them changes σ_s by
// under 0.1 % (tested).
inline constexpr int kMilkIntervals = 160;

struct MilkCoefficients {
  double sigma_s_per_m = 0.0, sigma_a_per_m = 0.0, g = 0.0;
};
MilkCoefficients milk_coefficients(const MilkComposition& milk, double wavelength_nm,
                                   int intervals = kMilkIntervals);

// The real index of milk's host (water, Hale & Querry 1973); the model takes it as milk's index.
double milk_host_index(double wavelength_nm);

struct MilkSpectra {
  TabulatedSpectrum sigma_s_per_m, sigma_a_per_m, g;
};
// 360–830 nm in 10 nm steps.
MilkSpectra milk_spectra(const MilkComposition& milk);

}  // namespace bouguer
