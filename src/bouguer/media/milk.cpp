#include "bouguer/media/milk.h"

#include <cmath>
#include <numbers>

#include "bouguer/core/csv.h"
#include "bouguer/spectra/spectrum_csv.h"

namespace bouguer::data {
extern const std::string_view milk_inputs;
}  // namespace bouguer::data

namespace bouguer {
namespace {

// Densities in g/ml (the model's: Walstra & Jenness 1984 via Frisvad et al. 2007).
constexpr double kFatDensity = 0.915, kCaseinDensity = 1.11, kMilkDensity = 1.030;
constexpr double kCaseinShareOfProtein = 0.76;  // of milk protein, by weight
constexpr double kCaseinIndex = 1.503;          // real index of casein micelles
// Casein micelles: log-normal in t = r/(150 nm − r), mean 43 nm radius, deviation 0.23 (in t).
constexpr double kCaseinRmaxM = 150e-9, kCaseinRvsM = 43e-9, kCaseinCs = 0.23;
constexpr double kFatRminM = 0.005e-6, kFatRmaxM = 10e-6;
// Riboflavin: 0.17 mg per 100 g of milk (Fox & McSweeney 1998), 376.3682 g/mol; absorptivity
// scaled to 33000 L/(mol cm) at 266.5 nm (Koziol 1966), where the tabulated absorbance is 0.25654.
constexpr double kRiboflavinMgPer100g = 0.17, kRiboflavinGPerMol = 376.3682;
constexpr double kRiboflavinPerMPerMolarPerAbsorbance = 3.3e6 / 0.25654;

struct Inputs {
  TabulatedSpectrum water_n, water_k, fat_n, fat_k, riboflavin;
};

const Inputs& inputs() {
  static const Inputs in = [] {
    const CsvTable t = parse_csv(data::milk_inputs, "data/scattering/milk-inputs.csv");
    return Inputs{spectrum_from_csv(t, 1), spectrum_from_csv(t, 2), spectrum_from_csv(t, 3),
                  spectrum_from_csv(t, 4), spectrum_from_csv(t, 5)};
  }();
  return in;
}

// Volume fraction of a component from its weight percentage and density.
double volume_fraction(double wt_percent, double density) { return (wt_percent / density) / (100.0 / kMilkDensity); }

// A log-normal volume distribution in t(r) with mean t(r_vs) and deviation c_s, evaluated as the
// model's authors do (the density in t taken as a density in r), normalised to `volume` and turned
// into a number density by the volume of one sphere.
struct LogNormalVolume {
  double alpha = 0.0, beta = 1.0, scale = 0.0;
  double (*transform)(double r_m) = nullptr;
  double volume_density(double r_m) const {
    const double t = transform(r_m);
    if (!(t > 0.0) || !std::isfinite(t)) return 0.0;
    const double z = (std::log(t) - alpha) / beta;
    return std::exp(-0.5 * z * z) / (t * beta * std::sqrt(2.0 * std::numbers::pi));
  }
  double number_density(double r_m) const {
    return scale * volume_density(r_m) / (4.0 / 3.0 * std::numbers::pi * r_m * r_m * r_m);
  }
};

double fat_transform(double r_m) { return r_m * 1e6; }  // µm
double casein_transform(double r_m) { return r_m / (kCaseinRmaxM - r_m); }

LogNormalVolume log_normal_volume(double t_vs, double c_s, double volume, double (*transform)(double), double r_min,
                                  double r_max, int intervals) {
  LogNormalVolume d;
  d.transform = transform;
  const double beta2 = std::log(c_s * c_s / (t_vs * t_vs) + 1.0);
  d.alpha = std::log(t_vs) - 0.5 * beta2;
  d.beta = std::sqrt(beta2);
  const double total = integrate_log_simpson([&](double r) { return d.volume_density(r); }, r_min, r_max, intervals);
  d.scale = total > 0.0 ? volume / total : 0.0;
  return d;
}

// σ_a of the host: water (Hale & Querry's k) plus riboflavin.
double host_sigma_a_per_m(double wavelength_nm) {
  const double wavelength_m = wavelength_nm * 1e-9;
  const double water = 4.0 * std::numbers::pi * eval(inputs().water_k, wavelength_nm) / wavelength_m;
  const double molar = (kRiboflavinMgPer100g / kRiboflavinGPerMol) / (100.0 / kMilkDensity);  // mol/L
  const double ribo = std::numbers::ln10 * molar * kRiboflavinPerMPerMolarPerAbsorbance *
                      eval(inputs().riboflavin, wavelength_nm);
  return water + ribo;
}

}  // namespace

FatGlobuleSize fat_globule_size(const MilkComposition& milk) {
  const double v = milk.fat_wt_percent;
  const double r_p50 = 7.481403922e-4 * v * v + 3.203991829e-2 * v + 0.1162155667;  // at 50 MPa
  const double r_p0 = v < 2.0 ? -0.2528033794 * v * v + 1.418606759 * v : 1.456189142 * std::pow(v, 0.36);
  const double log_50 = std::log10(50.0);
  const double beta = v > 0.0 ? std::log10(r_p0) : 0.0;
  const double alpha = beta / log_50 - std::log10(r_p50) / log_50;
  const double p = milk.homogenization_pressure_mpa;
  constexpr double kCv = 0.6;
  const double r = (p > 0.0 ? std::pow(10.0, -alpha * std::log10(p) + beta) : r_p0) / (kCv * kCv + 1.0);
  return {r, r * kCv};
}

double milk_host_index(double wavelength_nm) { return eval(inputs().water_n, wavelength_nm); }

MilkCoefficients milk_coefficients(const MilkComposition& milk, double wavelength_nm, int intervals) {
  const FatGlobuleSize fat_size = fat_globule_size(milk);
  const LogNormalVolume fat =
      log_normal_volume(fat_size.r_vs_um, fat_size.c_s_um, volume_fraction(milk.fat_wt_percent, kFatDensity),
                        fat_transform, kFatRminM, kFatRmaxM, intervals);
  const double casein_volume = kCaseinShareOfProtein * volume_fraction(milk.protein_wt_percent, kCaseinDensity);
  // The casein range stops just short of 150 nm, where t is infinite and the density zero.
  const double casein_rmin = 1e-9, casein_rmax = 0.999 * kCaseinRmaxM;
  const LogNormalVolume casein = log_normal_volume(casein_transform(kCaseinRvsM), kCaseinCs, casein_volume,
                                                   casein_transform, casein_rmin, casein_rmax, intervals);
  const double host = milk_host_index(wavelength_nm);
  const std::complex<double> fat_index{eval(inputs().fat_n, wavelength_nm), eval(inputs().fat_k, wavelength_nm)};
  const MieBulk f = mie_bulk({[&](double r) { return fat.number_density(r); }, kFatRminM, kFatRmaxM, fat_index}, host,
                             wavelength_nm, intervals);
  const MieBulk c = mie_bulk({[&](double r) { return casein.number_density(r); }, casein_rmin, casein_rmax,
                              {kCaseinIndex, 0.0}},
                             host, wavelength_nm, intervals);
  MilkCoefficients out;
  out.sigma_s_per_m = f.sigma_s_per_m + c.sigma_s_per_m;
  out.sigma_a_per_m = f.sigma_a_per_m + c.sigma_a_per_m + host_sigma_a_per_m(wavelength_nm);
  out.g = out.sigma_s_per_m > 0.0 ? (f.sigma_s_per_m * f.g + c.sigma_s_per_m * c.g) / out.sigma_s_per_m : 0.0;
  return out;
}

MilkSpectra milk_spectra(const MilkComposition& milk) {
  MilkSpectra s;
  for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm + 1e-9; nm += 10.0) {
    const MilkCoefficients c = milk_coefficients(milk, nm);
    for (TabulatedSpectrum* t : {&s.sigma_s_per_m, &s.sigma_a_per_m, &s.g}) t->wavelength_nm.push_back(nm);
    s.sigma_s_per_m.value.push_back(c.sigma_s_per_m);
    s.sigma_a_per_m.value.push_back(c.sigma_a_per_m);
    s.g.value.push_back(c.g);
  }
  return s;
}

}  // namespace bouguer
