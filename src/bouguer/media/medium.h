#pragma once
// What light meets between two surfaces: a closed set of media, each a small plain struct with
// the same verbs: a homogeneous absorber, and absorbers whose concentration varies in space; a
// scattering medium is a new alternative here, not a new branch in the integrators.
//
// Spectra are referred to by id into the scene's spectral tables (scene/spectral_tables.h),
// which are passed in with the path's wavelengths: a medium holds no per-mode data.
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "bouguer/media/concentration_field.h"
#include "bouguer/media/optical_depth.h"
#include "bouguer/media/phase.h"

#include "bouguer/spectra/sampled_spectrum.h"
#include "bouguer/spectra/sampled_wavelengths.h"

namespace bouguer {

// σ_a(λ) per metre (natural log, concentration applied), the same everywhere inside.
struct HomogeneousMedium {
  int sigma_a = -1;  // spectrum id (SpectrumRole::absorption); -1: clear
  bool absorbing = false;
};

// σ_a(x, λ) = Σ_k c_k(x)·ε_k(λ): absorbers each with its own concentration field. The optical
// depth of a segment is exact: ε_k times the field's column density (concentration_field.h).
struct FieldAbsorber {
  int epsilon = -1;  // spectrum id of σ_a per unit concentration (SpectrumRole::absorption)
  ConcentrationField field;
};
inline constexpr std::size_t kMaxAbsorbersPerMedium = 8;

struct FieldMedium {
  std::vector<FieldAbsorber> absorbers;  // 1 to kMaxAbsorbersPerMedium
};

// A medium that scatters: σ_s(x, λ) = ρ(x)·σ_s(λ), with a density field ρ (constant 1 when the
// medium is homogeneous) and one phase function. Its absorption is that of the absorbers (their
// fields already multiplied by ρ), and stays exact: the estimators track the scattering only
// (media/scattering.h) and multiply by the absorption's transmittance in closed form, so an
// absorbing, weakly scattering liquid keeps its colour free of absorption noise.
struct ScatteringMedium {
  std::vector<FieldAbsorber> absorbers;  // 0 to kMaxAbsorbersPerMedium
  int sigma_s = -1;                      // spectrum id of σ_s per metre at ρ = 1 (SpectrumRole::coefficient)
  ConcentrationField density = ConstantField{1.0};
  PhaseFunction phase;
};

using Medium = std::variant<HomogeneousMedium, FieldMedium, ScatteringMedium>;

// Whether light is lost along an infinite path inside (absorbed or scattered away).
inline bool absorbs(const Medium& m) {
  struct Visitor {
    bool operator()(const HomogeneousMedium& h) const { return h.absorbing; }
    bool operator()(const FieldMedium&) const { return true; }
    bool operator()(const ScatteringMedium&) const { return true; }
  };
  return std::visit(Visitor{}, m);
}

inline const ScatteringMedium* scattering(const Medium& m) { return std::get_if<ScatteringMedium>(&m); }

// Russian roulette is never played inside a medium that only absorbs: there the throughput falls
// because of absorption the estimator must follow to the end (docs/rendering.md). A scattering
// medium plays it by throughput: a path may scatter thousands of times there.
inline bool allows_roulette(const Medium& m) { return !absorbs(m) || scattering(m) != nullptr; }

// The optical-depth terms of a medium's absorbers over [t0, t1] (finite) along a ray: each ε_k
// with its column density ∫c_k dt.
struct AbsorberTerms {
  std::array<OpticalDepthTerm, kMaxAbsorbersPerMedium> terms;
  std::size_t n = 0;
  template <typename Ray>
  AbsorberTerms(const std::vector<FieldAbsorber>& absorbers, const Ray& ray, double t0, double t1) {
    for (const FieldAbsorber& a : absorbers)
      terms[n++] = {a.epsilon, column_density(a.field, ray.origin, ray.direction, t0, t1)};
  }
  std::span<const OpticalDepthTerm> span() const { return {terms.data(), n}; }
};

// exp(−Σ_k ε_k·∫c_k dt) over [t0, t1] (finite) for a medium's absorbers (one if there are none).
template <typename Tables, typename Ray, std::size_t N>
SampledSpectrum<N> absorbers_transmittance(const std::vector<FieldAbsorber>& absorbers, const Tables& tables,
                                           const Ray& ray, double t0, double t1, const SampledWavelengths<N>& w) {
  if (absorbers.empty()) return SampledSpectrum<N>::constant(1.0f);
  return tables.transmittance(AbsorberTerms(absorbers, ray, t0, t1).span(), w);
}
// The same at the one wavelength a walk still carries (w.secondary_terminated()).
template <typename Tables, typename Ray, std::size_t N>
float absorbers_kept_transmittance(const std::vector<FieldAbsorber>& absorbers, const Tables& tables, const Ray& ray,
                                   double t0, double t1, const SampledWavelengths<N>& w) {
  if (absorbers.empty()) return 1.0f;
  return tables.kept_transmittance(AbsorberTerms(absorbers, ray, t0, t1).span(), w);
}

// The fraction of light kept along ray.origin + t·ray.direction for t in [t0, t1] (t1 may be
// infinite: then zero in an absorber, one in a clear medium). Exact for every carried
// wavelength; deterministic (no tracking estimator for media that only absorb). For a scattering
// medium: its absorption only (the scattering is tracked, media/scattering.h).
template <typename Tables, typename Ray, std::size_t N>
SampledSpectrum<N> transmittance(const Medium& m, const Tables& tables, const Ray& ray, double t0, double t1,
                                 const SampledWavelengths<N>& w) {
  struct Visitor {
    const Tables& tables;
    const Ray& ray;
    double t0, t1;
    const SampledWavelengths<N>& w;
    SampledSpectrum<N> operator()(const HomogeneousMedium& h) const {
      if (!h.absorbing) return SampledSpectrum<N>::constant(1.0f);
      if (std::isinf(t1)) return SampledSpectrum<N>{};
      return tables.transmittance(h.sigma_a, t1 - t0, w);
    }
    SampledSpectrum<N> operator()(const FieldMedium& f) const {
      if (std::isinf(t1)) return SampledSpectrum<N>{};
      return absorbers_transmittance(f.absorbers, tables, ray, t0, t1, w);
    }
    SampledSpectrum<N> operator()(const ScatteringMedium& s) const {
      if (std::isinf(t1)) return SampledSpectrum<N>{};
      return absorbers_transmittance(s.absorbers, tables, ray, t0, t1, w);
    }
  };
  return std::visit(Visitor{tables, ray, t0, t1, w}, m);
}

// A medium of the scene: how light travels inside it and its refractive index, which the
// interfaces around it use.
struct SceneMedium {
  std::string name;    // for messages only
  Medium medium;
  int ior = -1;        // spectrum id of n(λ) (SpectrumRole::point)
  double ior_reference = 1.0;  // n at kReferenceWavelengthNm
  bool dispersive = false;     // n varies over 360–830 nm
  // Some surface has it behind (it is the inside or the contents of an object). A scattering
  // medium that is only ever in front of surfaces (an `outside` that nothing encloses) is open to
  // infinity, where a walk ends at a ray that escapes: walk_deep (integrators/walk.h) leaves it alone.
  bool enclosed = false;
  // Enclosed, not the world's, and of an index no other medium of a surface shares: every
  // boundary of it refracts (or is opaque), so a straight shadow ray from inside it to the
  // environment map always stops at one and brings nothing (compile.cpp: mark_sealed_media;
  // direct_light.cpp skips that ray, drawing its sample's numbers still).
  bool sealed = false;
};

// The index a path sees: the reference index until it has kept a single wavelength, after a
// dispersive interface, and the index at that wavelength from then on.
template <typename Tables, std::size_t N>
double eta(const SceneMedium& m, const Tables& tables, const SampledWavelengths<N>& w) {
  if (!w.secondary_terminated() || !m.dispersive) return m.ior_reference;
  return tables.at_nm(m.ior, w.single_nm);
}

}  // namespace bouguer
