#include "bouguer/media/concentration_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "bouguer/media/grid_field.h"

namespace bouguer {
namespace {

// c as a function of s alone.
double at_s(const LinearField& f, double s) { return std::max(0.0, f.value + f.slope_per_m * s); }
double at_s(const ExponentialField& f, double s) {
  return f.value * std::exp(-std::max(s / f.scale_length_m, -kExponentialFloor));
}
double at_s(const DiffusionField& f, double s) { return 0.5 * f.value * std::erfc(s / f.width_m); }
double at_s(const LayersField& f, double s) {
  const auto it = std::upper_bound(f.upper_s_m.begin(), f.upper_s_m.end(), s);
  const auto i = std::min<std::size_t>(static_cast<std::size_t>(it - f.upper_s_m.begin()), f.value.size() - 1);
  return f.value[i];
}

// ∫ c ds over [lo, hi] (lo < hi), in closed form.
double integral_s(const LinearField& f, double lo, double hi) {
  // The positive part of c0 + g·s: clip the interval to where it is positive.
  if (f.slope_per_m == 0.0) return std::max(0.0, f.value) * (hi - lo);
  const double root = -f.value / f.slope_per_m;
  if (f.slope_per_m > 0.0) lo = std::max(lo, root);
  else hi = std::min(hi, root);
  if (!(hi > lo)) return 0.0;
  return (hi - lo) * std::max(0.0, f.value + f.slope_per_m * 0.5 * (lo + hi));
}

double integral_s(const ExponentialField& f, double lo, double hi) {
  const double h = f.scale_length_m, floor_s = -kExponentialFloor * h;
  double sum = 0.0;
  if (lo < floor_s) {  // below the floor: the capped, constant concentration
    const double top = std::min(hi, floor_s);
    sum += f.value * std::exp(kExponentialFloor) * (top - lo);
    lo = top;
  }
  if (hi > lo) sum += f.value * h * std::exp(-lo / h) * -std::expm1(-(hi - lo) / h);  // stable for thin pieces
  return sum;
}

// F(x) = x·erfc(x) − exp(−x²)/√π, the antiderivative of erfc, for x >= 0 (where it has no
// large terms to cancel).
double erfc_antiderivative_nonnegative(double x) { return x * std::erfc(x) - std::exp(-x * x) / std::sqrt(std::numbers::pi); }

double integral_s(const DiffusionField& f, double lo, double hi) {
  const double w = f.width_m, xa = lo / w, xb = hi / w;
  // F(x) = 2x + F(−x) for x < 0 (erfc(x) = 2 − erfc(−x)): the 2x parts subtract exactly.
  auto difference = [](double a, double b) {  // F(b) − F(a)
    auto split = [](double x, double& linear) {
      if (x >= 0.0) return erfc_antiderivative_nonnegative(x);
      linear = 2.0 * x;
      return erfc_antiderivative_nonnegative(-x);
    };
    double la = 0.0, lb = 0.0;
    const double fa = split(a, la), fb = split(b, lb);
    return (lb - la) + (fb - fa);
  };
  if (xb - xa < 1e-6) return at_s(f, 0.5 * (lo + hi)) * (hi - lo);  // midpoint: relative error below 1e-12
  return std::max(0.0, 0.5 * f.value * w * difference(xa, xb));
}

double integral_s(const LayersField& f, double lo, double hi) {
  double sum = 0.0, below = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < f.value.size(); ++i) {
    const double above = i + 1 < f.value.size() ? f.upper_s_m[i] : std::numeric_limits<double>::infinity();
    const double a = std::max(lo, below), b = std::min(hi, above);
    if (b > a) sum += f.value[i] * (b - a);
    below = above;
  }
  return sum;
}

template <typename F>
double column_along_axis(const F& f, const Vec3& o, const Vec3& d, double t0, double t1) {
  const double s0 = f.frame.s_at(o), a = dot(d, f.frame.axis);
  const double sa = s0 + a * t0, sb = s0 + a * t1;
  const double lo = std::min(sa, sb), hi = std::max(sa, sb), dt = t1 - t0;
  // ∫c dt = Δt · (mean of c over [lo, hi] in s); across the axis (a -> 0) the mean is c itself.
  const double mean = hi > lo ? integral_s(f, lo, hi) / (hi - lo) : at_s(f, lo);
  return mean * dt;
}

}  // namespace

double concentration_at(const ConcentrationField& field, const Vec3& x) {
  return std::visit(
      [&](const auto& f) -> double {
        using F = std::decay_t<decltype(f)>;
        if constexpr (std::is_same_v<F, ConstantField>) return f.value;
        else if constexpr (std::is_same_v<F, GridField>) return grid_concentration_at(f, x);
        else return at_s(f, f.frame.s_at(x));
      },
      field);
}

double column_density(const ConcentrationField& field, const Vec3& o, const Vec3& d, double t0, double t1) {
  if (!(t1 > t0)) return 0.0;
  const double c = std::visit(
      [&](const auto& f) -> double {
        using F = std::decay_t<decltype(f)>;
        if constexpr (std::is_same_v<F, ConstantField>) return f.value * (t1 - t0);
        else if constexpr (std::is_same_v<F, GridField>) return grid_column_density(f, o, d, t0, t1);
        else return column_along_axis(f, o, d, t0, t1);
      },
      field);
  if (!(c > 0.0)) return 0.0;
  return std::min(c, kMaxColumnDensity);
}

double max_concentration(const ConcentrationField& field) {
  struct Visitor {
    double operator()(const ConstantField& f) const { return f.value; }
    double operator()(const LinearField& f) const {
      return f.slope_per_m == 0.0 ? std::max(0.0, f.value) : std::numeric_limits<double>::infinity();
    }
    double operator()(const ExponentialField& f) const {
      return f.value == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();  // grows towards −s
    }
    double operator()(const DiffusionField& f) const { return f.value; }
    double operator()(const LayersField& f) const { return *std::max_element(f.value.begin(), f.value.end()); }
    double operator()(const GridField& f) const { return f.values ? f.scale * f.values->max_value : 0.0; }
  };
  return std::visit(Visitor{}, field);
}

double max_concentration_on(const ConcentrationField& field, const Vec3& o, const Vec3& d, double t0, double t1) {
  return std::visit(
      [&](const auto& f) -> double {
        using F = std::decay_t<decltype(f)>;
        if constexpr (std::is_same_v<F, ConstantField>) {
          return f.value;
        } else if constexpr (std::is_same_v<F, LayersField>) {
          const double sa = f.frame.s_at(o + d * t0), sb = f.frame.s_at(o + d * t1);
          const double lo = std::min(sa, sb), hi = std::max(sa, sb);
          double peak = 0.0, below = -std::numeric_limits<double>::infinity();
          for (std::size_t i = 0; i < f.value.size(); ++i) {
            const double above = i + 1 < f.value.size() ? f.upper_s_m[i] : std::numeric_limits<double>::infinity();
            if (hi >= below && lo < above) peak = std::max(peak, f.value[i]);
            below = above;
          }
          return peak;
        } else if constexpr (std::is_same_v<F, GridField>) {
          return grid_max_concentration_on(f, o, d, t0, t1);
        } else {
          return std::max(at_s(f, f.frame.s_at(o + d * t0)), at_s(f, f.frame.s_at(o + d * t1)));
        }
      },
      field);
}

ConcentrationField scaled(ConcentrationField field, double factor) {
  std::visit(
      [&](auto& f) {
        using F = std::decay_t<decltype(f)>;
        if constexpr (std::is_same_v<F, LayersField>) {
          for (double& v : f.value) v *= factor;
        } else if constexpr (std::is_same_v<F, LinearField>) {
          f.value *= factor;
          f.slope_per_m *= factor;
        } else if constexpr (std::is_same_v<F, GridField>) {
          f.scale *= factor;  // the shared values stay as they are
        } else {
          f.value *= factor;
        }
      },
      field);
  return field;
}

}  // namespace bouguer
