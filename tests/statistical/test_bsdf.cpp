// Every BSDF's sampling against its evaluation: a chi-square goodness-of-fit test of the sampled
// directions against the density `pdf` claims (as in pbrt and Mitsuba), plus weight = eval/pdf,
// energy conservation and reciprocity. The significance level is 1 % over all cases together
// (Bonferroni), so a correct sampler fails once in a hundred suite runs at most; the fixed seed
// makes a run repeatable.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "bouguer/materials/bsdf.h"
#include "bouguer/materials/fresnel.h"
#include "bouguer/media/phase.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kThetaBins = 24, kPhiBins = 48, kSamples = 400000, kCases = 17;

// Regularised upper incomplete gamma Q(a, x): series for x < a + 1, continued fraction otherwise.
double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 10000 && std::abs(term) > std::abs(sum) * 1e-15; ++n) sum += term *= x / (a + n);
    return 1.0 - sum * std::exp(log_prefix);
  }
  double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    d = std::abs(d) < 1e-300 ? 1e-300 : d;
    c = b + an / c;
    c = std::abs(c) < 1e-300 ? 1e-300 : c;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15) break;
  }
  return std::exp(log_prefix) * h;
}

Vec3 direction(double cos_theta, double phi) {
  const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

using Sampler = std::function<std::optional<BsdfSample>(std::mt19937_64&)>;
using Density = std::function<double(const Vec3&)>;

// Bins over (cos θ, φ) cover the whole sphere with equal solid angle each.
void chi_square(const Sampler& sample, const Density& pdf, const std::string& what) {
  std::mt19937_64 rng(12345);
  std::vector<double> observed(kThetaBins * kPhiBins, 0.0), expected(kThetaBins * kPhiBins, 0.0);
  for (int i = 0; i < kSamples; ++i) {
    const auto s = sample(rng);
    if (!s) continue;
    const int t = std::clamp(static_cast<int>((s->wi.z + 1.0) / 2.0 * kThetaBins), 0, kThetaBins - 1);
    double phi = std::atan2(s->wi.y, s->wi.x);
    if (phi < 0) phi += 2 * kPi;
    const int p = std::clamp(static_cast<int>(phi / (2 * kPi) * kPhiBins), 0, kPhiBins - 1);
    observed[t * kPhiBins + p] += 1.0;
  }
  // Expected counts: the density integrated over each bin, midpoint rule in θ (fine: lobes of
  // rough surfaces can be narrow near the poles) and φ, with dω = sin θ dθ dφ.
  constexpr int sub_theta = 64, sub_phi = 8;
  const double dp = 2 * kPi / kPhiBins;
  for (int t = 0; t < kThetaBins; ++t) {
    const double theta_hi = std::acos(-1.0 + 2.0 * t / kThetaBins), theta_lo = std::acos(-1.0 + 2.0 * (t + 1) / kThetaBins);
    const double dt = (theta_hi - theta_lo) / sub_theta;
    for (int p = 0; p < kPhiBins; ++p) {
      double integral = 0.0;
      for (int i = 0; i < sub_theta; ++i) {
        const double theta = theta_lo + (i + 0.5) * dt;
        for (int j = 0; j < sub_phi; ++j)
          integral += pdf(direction(std::cos(theta), (p + (j + 0.5) / sub_phi) * dp)) * std::sin(theta);
      }
      expected[t * kPhiBins + p] = integral * dt * dp / sub_phi * kSamples;
    }
  }
  // Pool bins expecting fewer than 5 samples, as the test requires.
  double chi2 = 0.0, pooled_obs = 0.0, pooled_exp = 0.0;
  int dof = -1;
  for (std::size_t k = 0; k < observed.size(); ++k) {
    if (expected[k] < 5.0) {
      pooled_obs += observed[k];
      pooled_exp += expected[k];
      continue;
    }
    chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    ++dof;
  }
  if (pooled_exp >= 5.0) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++dof;
  } else {
    EXPECT_LT(pooled_obs, 5.0 + 5.0 * std::sqrt(std::max(pooled_exp, 1.0))) << what << ": samples where pdf is ~0";
  }
  ASSERT_GT(dof, 10) << what;
  const double p_value = gamma_q(dof / 2.0, chi2 / 2.0);
  EXPECT_GT(p_value, 0.01 / kCases) << what << ": chi² = " << chi2 << " with " << dof << " degrees of freedom";
}

// For returned samples: pdf and weight agree with pdf() and eval()/pdf(), and weights never
// exceed 1 (these BSDFs absorb nothing but through Fresnel, which is excluded or ≤ 1).
void consistency(const Sampler& sample, const std::function<double(const Vec3&)>& eval, const Density& pdf,
                 const std::string& what) {
  std::mt19937_64 rng(777);
  double sum = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const auto s = sample(rng);
    if (!s) continue;
    ASSERT_NEAR(s->pdf, pdf(s->wi), 1e-9 * std::max(1.0, s->pdf)) << what;
    ASSERT_NEAR(s->weight, eval(s->wi) / s->pdf, 1e-9) << what;
    ASSERT_LE(s->weight, 1.0 + 1e-9) << what;
    sum += s->weight;
  }
  EXPECT_LE(sum / n, 1.0 + 1e-9) << what << ": albedo";
}

struct Case {
  std::string name;
  Vec3 wo;
  Sampler sample;
  std::function<double(const Vec3&)> eval;
  Density pdf;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto add_wo = [&](const std::string& name, const Vec3& wo, auto bsdf, bool three) {
    Case c;
    c.name = name;
    c.wo = wo;
    c.sample = [bsdf, wo, three, u](std::mt19937_64& rng) mutable {
      if constexpr (requires { bsdf.sample(wo, 0.0, 0.0, 0.0); }) {
        const double a = u(rng), b = u(rng), d = u(rng);
        return bsdf.sample(wo, a, b, d);
      } else {
        (void)three;
        const double a = u(rng), b = u(rng);
        return bsdf.sample(wo, a, b);
      }
    };
    c.eval = [bsdf, wo](const Vec3& wi) { return bsdf.eval(wo, wi); };
    c.pdf = [bsdf, wo](const Vec3& wi) { return bsdf.pdf(wo, wi); };
    out.push_back(c);
  };
  const Vec3 near_normal = normalize(Vec3{0.2, 0.1, 0.95}), oblique = normalize(Vec3{0.8, -0.3, 0.35});
  add_wo("diffuse", near_normal, DiffuseBsdf{}, false);
  add_wo("diffuse from below", -oblique, DiffuseBsdf{}, false);
  for (const double alpha : {0.08, 0.3, 0.7}) {
    add_wo("conductor a=" + std::to_string(alpha), oblique, ConductorBsdf{{alpha}}, false);
    for (const Vec3& wo : {near_normal, oblique, -near_normal, -oblique})
      add_wo("rough dielectric a=" + std::to_string(alpha) + (wo.z > 0 ? " outside" : " inside") +
                 (std::abs(wo.z) > 0.9 ? " near normal" : " oblique"),
             wo, RoughDielectricBsdf{{alpha}, 1.0, 1.5}, true);
  }
  return out;
}

TEST(Bsdf, SamplingMatchesDensityChiSquare) {
  const auto all = cases();
  ASSERT_EQ(all.size(), static_cast<std::size_t>(kCases));  // the Bonferroni count
  for (const Case& c : all) chi_square(c.sample, c.pdf, c.name);
}

// Phase functions of scattering media (media/phase.h) by the same test: sampled directions of
// travel against the density, for light arriving along an oblique direction.
TEST(Phase, SamplingMatchesDensityChiSquare) {
  const Vec3 in = normalize(Vec3{0.3, -0.4, 0.85});
  const PhaseFunction phases[] = {IsotropicPhase{}, HenyeyGreensteinPhase{0.7}, HenyeyGreensteinPhase{-0.5},
                                  HenyeyGreensteinPhase{0.95}};
  for (const PhaseFunction& phase : phases) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const std::string name = "phase g=" + std::to_string(mean_cosine(phase));
    chi_square(
        [&](std::mt19937_64& rng) -> std::optional<BsdfSample> {
          const double a = u(rng), b = u(rng);
          const PhaseSample s = sample_phase(phase, in, a, b);
          return BsdfSample{s.out, s.pdf, 1.0, false};
        },
        [&](const Vec3& out) { return phase_value(phase, in, out); }, name);
  }
}

// Normalised over the sphere, with the mean cosine it claims (midpoint rule in cos θ).
TEST(Phase, NormalisedWithItsMeanCosine) {
  const Vec3 in{0, 0, 1};
  for (const double g : {0.0, 0.3, 0.7, -0.8, 0.95}) {
    const PhaseFunction phase = HenyeyGreensteinPhase{g};
    double total = 0.0, mean = 0.0;
    const int n = 2000000;
    for (int i = 0; i < n; ++i) {
      const double c = -1.0 + (i + 0.5) * 2.0 / n;
      const double p = phase_value(phase, in, direction(c, 0.0)) * 2.0 * kPi * 2.0 / n;
      total += p;
      mean += p * c;
    }
    EXPECT_NEAR(total, 1.0, 1e-6) << g;
    EXPECT_NEAR(mean, g, 1e-6) << g;
  }
  EXPECT_NEAR(phase_value(IsotropicPhase{}, in, in), 1.0 / (4.0 * kPi), 1e-15);
}

TEST(Bsdf, SampleWeightsAreEvalOverPdfAndConserveEnergy) {
  for (const Case& c : cases()) consistency(c.sample, c.eval, c.pdf, c.name);
}

// f(wo, wi) = f(wi, wo) for reflection; across the dielectric, without η² radiance scaling,
// f(wo, wi) / η_wi² = f(wi, wo) / η_wo².
TEST(Bsdf, Reciprocity) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const ConductorBsdf conductor{{0.3}};
  const RoughDielectricBsdf dielectric{{0.3}, 1.0, 1.5};
  const DiffuseBsdf diffuse;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 a = normalize(Vec3{u(rng), u(rng), u(rng)}), b = normalize(Vec3{u(rng), u(rng), u(rng)});
    auto f = [](const auto& bsdf, const Vec3& wo, const Vec3& wi) { return bsdf.eval(wo, wi) / std::abs(wi.z); };
    EXPECT_NEAR(f(conductor, a, b), f(conductor, b, a), 1e-9 * std::max(1.0, f(conductor, a, b)));
    EXPECT_NEAR(f(diffuse, a, b), f(diffuse, b, a), 1e-12);
    const double eta_a = a.z > 0 ? 1.0 : 1.5, eta_b = b.z > 0 ? 1.0 : 1.5;
    const double lhs = f(dielectric, a, b) / (eta_b * eta_b), rhs = f(dielectric, b, a) / (eta_a * eta_a);
    EXPECT_NEAR(lhs, rhs, 1e-9 * std::max(1.0, lhs));
  }
}

// With energy compensation, a lossless rough interface scatters all light from every direction:
// the mean sample weight (reflection + transmission) is 1. The tolerance is 4 standard errors of
// the estimate (the weights' own spread over n samples) plus 0.2 % for the tabulation.
TEST(Bsdf, RoughDielectricCompensationKeepsAllEnergy) {
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const double alpha : {0.08, 0.3, 0.7}) {
    for (const auto& [eta_out, eta_in] : {std::pair{1.0, 1.5}, std::pair{1.33, 1.5}, std::pair{1.0, 2.42}}) {
      const DielectricAlbedo table = DielectricAlbedo::compute(alpha, eta_out, eta_in);
      const RoughDielectricBsdf plain{{alpha}, eta_out, eta_in}, compensated{{alpha}, eta_out, eta_in, &table};
      for (const double mu : {0.05, 0.3, 0.7, 0.99}) {
        for (const double side : {1.0, -1.0}) {
          const Vec3 wo{std::sqrt(1.0 - mu * mu), 0.0, side * mu};
          const int n = 100000;
          double sum = 0.0, sum2 = 0.0, plain_sum = 0.0;
          for (int i = 0; i < n; ++i) {
            const double a = u(rng), b = u(rng), c = u(rng);
            if (const auto s = compensated.sample(wo, a, b, c)) {
              sum += s->weight;
              sum2 += s->weight * s->weight;
            }
            if (const auto s = plain.sample(wo, a, b, c)) plain_sum += s->weight;
          }
          const double mean = sum / n, sigma = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
          const std::string what = "alpha " + std::to_string(alpha) + " eta " + std::to_string(eta_out) + "|" +
                                   std::to_string(eta_in) + " cos " + std::to_string(side * mu);
          EXPECT_NEAR(mean, 1.0, 4.0 * sigma + 0.002) << what << " (single scattering: " << plain_sum / n << ")";
          EXPECT_LE(plain_sum / n, 1.0 + 4.0 * sigma) << what;
        }
      }
    }
  }
}

// The microfacet distribution is normalised: ∫ D(m) cos θm dωm = 1.
TEST(Bsdf, GgxIsNormalised) {
  for (const double alpha : {0.05, 0.3, 0.9}) {
    const GgxDistribution ggx{alpha};
    double sum = 0.0;
    const int nt = 4000, np = 64;
    for (int i = 0; i < nt; ++i) {
      // Substitution cos θ = 1 − s² concentrates points near the normal where D peaks.
      const double s = (i + 0.5) / nt, c = 1.0 - s * s, dc = 2.0 * s / nt;
      for (int j = 0; j < np; ++j) sum += ggx.D(direction(c, 2 * kPi * (j + 0.5) / np)) * c * dc * 2 * kPi / np;
    }
    EXPECT_NEAR(sum, 1.0, 2e-3) << alpha;
  }
}

TEST(Bsdf, ConductorFresnelLimits) {
  // A dielectric "conductor" (k = 0) equals the dielectric formula; k → large gives a mirror.
  for (const double c : {1.0, 0.7, 0.2})
    EXPECT_NEAR(fresnel_conductor(c, 1.0, {1.5, 0.0}), fresnel_dielectric(c, 1.0, 1.5), 1e-12);
  // Gold at 600 nm, n = 0.25 + 3.0i (Johnson & Christy): R(normal) = ((n−1)² + k²)/((n+1)² + k²).
  EXPECT_NEAR(fresnel_conductor(1.0, 1.0, {0.25, 3.0}), (0.5625 + 9.0) / (1.5625 + 9.0), 1e-12);
  EXPECT_NEAR(fresnel_conductor(0.0, 1.0, {0.25, 3.0}), 1.0, 1e-12);
}

TEST(Bsdf, IncompleteGammaMatchesKnownValues) {
  EXPECT_NEAR(gamma_q(1.0, 2.0), std::exp(-2.0), 1e-12);          // Q(1, x) = e^−x
  EXPECT_NEAR(gamma_q(0.5, 0.5), std::erfc(std::sqrt(0.5)), 1e-12);  // Q(1/2, x) = erfc(√x)
  // Integer a: Q(n, x) = e^−x Σ_{k<n} x^k / k!, on both sides of the series/fraction switch.
  for (const auto& [n, x] : {std::pair{10, 30.0}, std::pair{5, 3.0}, std::pair{40, 35.0}}) {
    double sum = 0.0, term = 1.0;
    for (int k = 0; k < n; ++k) sum += term, term *= x / (k + 1);
    EXPECT_NEAR(gamma_q(n, x), std::exp(-x) * sum, 1e-12) << n << " " << x;
  }
}

}  // namespace
}  // namespace bouguer
