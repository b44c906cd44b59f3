// Build-time generator of the RGB-to-spectrum table (Jakob & Hanika 2019, "A Low-Dimensional
// Function Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2)).
//
// Every linear Rec.709 colour c in [0,1]³ gets the smooth reflectance
//     r(λ) = S(c0 t² + c1 t + c2),  S(x) = 1/2 + x / (2 √(1 + x²)),  t = (λ − 360 nm) / 470 nm,
// whose colour under D65 (CIE 1931, the renderer's own tables) matches c: Gauss–Newton on the
// CIELAB difference, warm-started from the neighbouring cell. The table is indexed like the paper's:
// the largest channel z picks a slice (nodes packed towards 0 and 1 by a double smoothstep), the
// other two channels divided by it give (x, y) on a uniform grid.
//
// usage: bouguer_rgb2spec_gen OUT.cpp   (writes the table as C++ source)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "bouguer/core/math.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"
#include "bouguer/spectra/rgb_to_spectrum_layout.h"

using namespace bouguer;

namespace {

constexpr int kNodes = 95;  // 5 nm nodes, 360–830 nm
constexpr double kStepNm = (kLambdaMaxNm - kLambdaMinNm) / (kNodes - 1);

double sigmoid(double x) { return 0.5 + x / (2.0 * std::sqrt(1.0 + x * x)); }

// XYZ weights per node: the 1 nm products D65·x̄ (normalised so that r ≡ 1 gives Y = 1) integrated
// against the hat function of each node, so the 5 nm quadrature is exact for spectra linear
// between nodes.
struct Weights {
  std::vector<Vec3> w = std::vector<Vec3>(kNodes);
  Vec3 white;
};

Weights make_weights() {
  const ObserverTable& cmf = observer_table(Observer::cie1931_2deg);
  const Spectrum d65 = named_illuminant("D65", 1.0);
  Weights out;
  double y_sum = 0.0;
  for (int i = 0; i < kCmfCount; ++i) y_sum += eval(d65, kLambdaMinNm + i) * cmf.ybar[i];
  for (int i = 0; i < kCmfCount; ++i) {
    const double nm = kLambdaMinNm + i, s = eval(d65, nm) / y_sum;
    const Vec3 xyz{s * cmf.xbar[i], s * cmf.ybar[i], s * cmf.zbar[i]};
    const double pos = (nm - kLambdaMinNm) / kStepNm;
    const int k = std::min(static_cast<int>(pos), kNodes - 2);
    const double f = pos - k;
    out.w[k] = out.w[k] + xyz * (1.0 - f);
    out.w[k + 1] = out.w[k + 1] + xyz * f;
  }
  for (const Vec3& v : out.w) out.white = out.white + v;
  return out;
}

Lab lab_of(const Weights& w, const std::array<double, 3>& c) {
  Vec3 xyz;
  for (int k = 0; k < kNodes; ++k) {
    const double t = static_cast<double>(k) / (kNodes - 1);
    xyz = xyz + w.w[k] * sigmoid((c[0] * t + c[1]) * t + c[2]);
  }
  return xyz_to_lab(xyz, w.white);
}

Vec3 residual(const Weights& w, const Lab& target, const std::array<double, 3>& c) {
  const Lab l = lab_of(w, c);
  return {target.L - l.L, target.a - l.a, target.b - l.b};
}

// Gauss–Newton with a forward-difference Jacobian; returns the final CIELAB error.
double fit(const Weights& w, const Lab& target, std::array<double, 3>& c) {
  double error = 0.0;
  for (int it = 0; it < 30; ++it) {
    const Vec3 r = residual(w, target, c);
    error = length(r);
    if (error < 1e-6) break;
    Mat3 jacobian;
    for (int j = 0; j < 3; ++j) {
      std::array<double, 3> cp = c;
      const double eps = 1e-4;
      cp[j] += eps;
      const Vec3 d = (r - residual(w, target, cp)) / eps;  // ∂Lab_fit/∂c_j
      jacobian.m[0][j] = d.x;
      jacobian.m[1][j] = d.y;
      jacobian.m[2][j] = d.z;
    }
    const Vec3 step = inverse(jacobian) * r;
    if (!std::isfinite(step.x) || !std::isfinite(step.y) || !std::isfinite(step.z)) break;
    // Damped: halve the step until the error drops (plain Gauss–Newton overshoots on dark colours).
    bool improved = false;
    for (double damping = 1.0; damping > 1e-3 && !improved; damping *= 0.5) {
      std::array<double, 3> next{c[0] + damping * step.x, c[1] + damping * step.y, c[2] + damping * step.z};
      // Keep the polynomial in a range where the sigmoid stays smooth (the paper's safeguard).
      const double m = std::max({std::abs(next[0]), std::abs(next[1]), std::abs(next[2])});
      if (m > 200.0)
        for (double& x : next) x *= 200.0 / m;
      if (length(residual(w, target, next)) < error) {
        c = next;
        improved = true;
      }
    }
    if (!improved) break;
  }
  return error;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.cpp\n", argv[0]);
    return 2;
  }
  constexpr int res = kRgbTableResolution;
  const Weights weights = make_weights();
  const Mat3 to_xyz = rgb_to_xyz_matrix(kRec709);
  std::vector<float> table(static_cast<std::size_t>(3 * res * res * res * 3));
  // Worst CIELAB error per row: over all cells but black, and over cells whose largest channel is
  // at least 0.05 (the darkest saturated colours fit worse: the sigmoid cannot get as narrow).
  std::vector<double> worst(3 * res, 0.0), worst_bright(3 * res, 0.0);
  tbb::parallel_for(0, 3 * res, [&](int row) {
    const int l = row / res, j = row % res;
    for (int i = 0; i < res; ++i) {
      const double x = static_cast<double>(i) / (res - 1), y = static_cast<double>(j) / (res - 1);
      const int start = res / 5;
      for (const int direction : {+1, -1}) {
        std::array<double, 3> c{0.0, 0.0, 0.0};
        // Both sweeps begin at the same moderate brightness, from which a cold start converges.
        for (int k = start; k >= 0 && k < res; k += direction) {
          const double z = rgb_table_z_node(k);
          double rgb[3];
          rgb[l] = z;
          rgb[(l + 1) % 3] = x * z;
          rgb[(l + 2) % 3] = y * z;
          const Vec3 xyz = to_xyz * Vec3{rgb[0], rgb[1], rgb[2]};
          const double err = fit(weights, xyz_to_lab(xyz, weights.white), c);
          if (k > 0) worst[row] = std::max(worst[row], err);  // k = 0 is black: reachable only in the limit
          if (z >= 0.05) worst_bright[row] = std::max(worst_bright[row], err);
          if (k > 0 && err > 0.01 && std::getenv("RGB2SPEC_DEBUG")) std::fprintf(stderr, "l %d k %d j %d i %d z %.4f err %.3g\n", l, k, j, i, z, err);
          const std::size_t at = ((static_cast<std::size_t>(l * res + k) * res + j) * res + i) * 3;
          for (int q = 0; q < 3; ++q) table[at + q] = static_cast<float>(c[q]);
        }
      }
    }
  });
  double max_err = 0.0, max_err_bright = 0.0;
  for (double e : worst) max_err = std::max(max_err, e);
  for (double e : worst_bright) max_err_bright = std::max(max_err_bright, e);

  std::ofstream out(argv[1]);
  out << "// Generated by tools/rgb2spec_gen.cpp at build time; do not edit.\n"
      << "// Jakob & Hanika 2019 sigmoid-polynomial coefficients for linear Rec.709 under D65, CIE 1931.\n"
      << "// Largest CIELAB error of the fit: " << max_err_bright << " where max(r, g, b) >= 0.05, " << max_err
      << " over all cells but black\n"
      << "#include \"bouguer/spectra/rgb_to_spectrum_layout.h\"\n"
      << "namespace bouguer::data {\nextern const float kRgbToSpectrumCoefficients[] = {\n";
  char buf[32];
  for (std::size_t n = 0; n < table.size(); ++n) {
    std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(table[n]));
    const std::string literal = buf;
    out << literal << (literal.find_first_of(".e") == std::string::npos ? ".f," : "f,") << ((n + 1) % 12 == 0 ? "\n" : "");
  }
  out << "};\n}  // namespace bouguer::data\n";
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", argv[1]);
    return 1;
  }
  std::printf("RGB-to-spectrum table: %d³ × 3 cells; largest CIELAB fit error %.2g where max(r, g, b) >= 0.05, %.2g "
              "over all but black\n",
              res, max_err_bright, max_err);
  return 0;
}
