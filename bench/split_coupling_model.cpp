// How closely can two walks of one wavelength in a glass of milk be kept in step? A model, not the
// renderer (docs/performance.md, "How far the split walks can be kept in step").
//
// The path tracer splits a camera path that enters a dense chromatic medium into walks of one
// wavelength each, all drawing the same random numbers (integrators/dense_media.h), so that their
// values correlate and the pixel's colour is quieter than four independent walks would make it.
// This program asks how far any choice of shared numbers can take that correlation in the
// whole-milk tumbler's geometry, without the renderer's other parts: two walks (scattering
// coefficients sigma_1 and sigma_2 = 20 000 per m, Henyey–Greenstein g = 0.864, no absorption)
// enter a cylinder of milk (radius 29 mm, the tumbler's inside; 1 m for a nearly flat wall) at its
// wall, inside a 2.5 mm glass wall (n 1.33 | 1.52 | 1, Fresnel's choice at each interface, total
// internal reflection included), and each leaves with a direction whose value is a light from one
// side (cos⁴ towards it, plus a floor: a stand-in for the studio map's softbox). Each coupling
// below gives every walk its exact distribution (only which numbers it reads changes), so each
// walk alone is unbiased; they differ only in how the two walks' values correlate:
//   scaled      the renderer's: the k-th event of each walk reads the k-th numbers, the azimuth
//               about the direction from a frame of the direction alone. The walks are copies
//               scaled about the entry point; below a flat wall they leave at the same event.
//   wall-frame  the same numbers, the azimuth measured from the plane of the direction and the
//               nearest wall's normal, so that the walks' states relative to the wall (depth in
//               mean free paths, direction against the normal) evolve alike where a wall curves.
//   re-keyed    the scaled copies' frame, the numbers keyed by (contacts with the wall, events
//               since the last), so that walks that touched the wall at different events draw the
//               same numbers after it.
// Reports per case the correlation of the two walks' values (its standard error about 0.01 at
// 2000 pairs) and the share of pairs that leave at the same event. Deterministic (counter-based
// numbers); about 10 seconds on one core.
//
//   build/bench/bouguer_split_coupling_model [pairs]
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numbers>

namespace {

struct Vec {
  double x, y, z;
};
Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec operator*(double s, Vec a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
Vec normalize(Vec a) { return (1.0 / std::sqrt(dot(a, a))) * a; }

constexpr double kG = 0.864;
constexpr double kWallM = 0.0025;
constexpr double kSigmaRedPerM = 20000.0;

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
// The number `slot` of event (a, b) of the walk pair `seed`, in [0, 1).
double number(std::uint64_t seed, std::uint64_t a, std::uint64_t b, int slot) {
  return static_cast<double>(mix(mix(mix(seed) ^ a) ^ (b * 8 + static_cast<std::uint64_t>(slot))) >> 11) * 0x1.0p-53;
}

double hg_cos(double u) {
  const double s = (1 - kG * kG) / (1 - kG + 2 * kG * u);
  return (1 + kG * kG - s * s) / (2 * kG);
}
// Duff et al.'s orthonormal basis about n.
void basis(Vec n, Vec& b1, Vec& b2) {
  const double s = n.z >= 0 ? 1.0 : -1.0, a = -1 / (s + n.z), b = n.x * n.y * a;
  b1 = {1 + s * n.x * n.x * a, s * b, -s * n.x};
  b2 = {b, s + n.y * n.y * a, -n.y};
}
// Unpolarised Fresnel reflectance from index n1 into n2 at incidence cosine ci; cos_t the
// transmitted cosine (1 where the light is totally reflected).
double fresnel(double ci, double n1, double n2, double& cos_t) {
  const double st2 = (n1 / n2) * (n1 / n2) * (1 - ci * ci);
  if (st2 >= 1) return 1.0;
  cos_t = std::sqrt(1 - st2);
  const double rs = (n1 * ci - n2 * cos_t) / (n1 * ci + n2 * cos_t);
  const double rp = (n2 * ci - n1 * cos_t) / (n2 * ci + n1 * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

enum class Coupling { scaled, wall_frame, rekeyed };

struct Exit {
  bool left = false;
  int events = 0;
  Vec direction{};
};

// One walk of scattering coefficient sigma from p along d inside the cylinder x² + y² < r_m².
Exit walk(double sigma_per_m, double r_m, std::uint64_t seed, Coupling coupling, Vec p, Vec d) {
  int contacts = 0, since = 0;
  for (int k = 0; k < 200000; ++k) {
    const bool rekey = coupling == Coupling::rekeyed;
    const std::uint64_t a = rekey ? static_cast<std::uint64_t>(contacts) : 0;
    const std::uint64_t b = static_cast<std::uint64_t>(rekey ? since : k);
    ++since;
    const double flight_m = -std::log(1 - number(seed, a, b, 0)) / sigma_per_m;
    const double qa = d.x * d.x + d.y * d.y, qb = 2 * (p.x * d.x + p.y * d.y), qc = p.x * p.x + p.y * p.y - r_m * r_m;
    const double wall_m = qa > 0 ? (-qb + std::sqrt(std::max(0.0, qb * qb - 4 * qa * qc))) / (2 * qa) : 1e30;
    if (wall_m < flight_m) {
      // At the wall: milk | glass | air, each interface's choice from this event's numbers.
      p = p + wall_m * d;
      bool in_glass = false;
      for (int bounce = 0; bounce < 64; ++bounce) {
        const double r = std::sqrt(p.x * p.x + p.y * p.y);
        const Vec n = (1.0 / r) * Vec{p.x, p.y, 0};  // outward
        const bool outgoing = dot(d, n) > 0;
        const double ci = std::fabs(dot(d, n));
        const double n1 = in_glass ? 1.52 : 1.33;
        const double n2 = !in_glass ? 1.52 : (outgoing && r > r_m + 0.5 * kWallM ? 1.0 : 1.33);
        double cos_t = 1.0;
        const double f = fresnel(ci, n1, n2, cos_t);
        if (number(seed, a, b * 64 + static_cast<std::uint64_t>(bounce), 3) < f) {
          d = d + (-2 * dot(d, n)) * n;
        } else {
          const Vec towards = outgoing ? n : -1.0 * n;
          const double eta = n1 / n2;
          d = normalize(eta * d + (cos_t - eta * ci) * towards);
          if (n2 == 1.0) return {true, k, d};
          in_glass = !in_glass;
        }
        if (!in_glass) {
          p = p + (-1e-12) * n;
          break;
        }
        // On through the glass to its next face.
        const double ga = d.x * d.x + d.y * d.y, gb = 2 * (p.x * d.x + p.y * d.y);
        double t = 1e30;
        for (const double face_m : {r_m, r_m + kWallM}) {
          const double disc = gb * gb - 4 * ga * (p.x * p.x + p.y * p.y - face_m * face_m);
          if (disc < 0) continue;
          for (const double c : {(-gb - std::sqrt(disc)) / (2 * ga), (-gb + std::sqrt(disc)) / (2 * ga)})
            if (c > 1e-12 && c < t) t = c;
        }
        if (t >= 1e29) return {true, k, d};
        p = p + t * d;
      }
      ++contacts;
      since = 0;
      continue;
    }
    p = p + flight_m * d;
    const double ct = hg_cos(number(seed, a, b, 1)), st = std::sqrt(std::max(0.0, 1 - ct * ct));
    const double phi = 2 * std::numbers::pi * number(seed, a, b, 2);
    Vec e1, e2;
    basis(d, e1, e2);
    if (coupling == Coupling::wall_frame) {
      const Vec n = normalize(Vec{p.x, p.y, 0});
      const Vec q = n + (-dot(n, d)) * d;
      const double l = std::sqrt(dot(q, q));
      if (l > 1e-9) {
        e1 = (1 / l) * q;
        e2 = cross(d, e1);
      }
    }
    d = normalize(ct * d + st * (std::cos(phi) * e1 + std::sin(phi) * e2));
  }
  return {};
}

void report(const char* name, double sigma_per_m, double r_m, Coupling coupling, int pairs) {
  const Vec light = normalize(Vec{0.3, 0.8, 0.5});
  auto value = [&](Vec o) {
    const double c = dot(o, light);
    return c > 0 ? 5 * std::pow(c, 4) : 0.05;
  };
  double s1 = 0, s2 = 0, s11 = 0, s22 = 0, s12 = 0;
  int n = 0, same = 0;
  for (int i = 0; i < pairs; ++i) {
    const std::uint64_t seed = mix(static_cast<std::uint64_t>(i) + 12345);
    // Entry on the wall's lit side, heading inwards within about ±17°.
    const double angle = number(seed, 99, 0, 0) - 0.5;
    const Vec p{r_m * std::cos(angle) * (1 - 1e-12), r_m * std::sin(angle) * (1 - 1e-12), 0};
    const Vec inward = -1.0 * Vec{std::cos(angle), std::sin(angle), 0};
    const Vec spread{0, (number(seed, 99, 0, 1) - 0.5) * 0.6, (number(seed, 99, 0, 2) - 0.5) * 0.6};
    const Vec d = normalize(inward + spread);
    const Exit x = walk(sigma_per_m, r_m, seed, coupling, p, d);
    const Exit y = walk(kSigmaRedPerM, r_m, seed, coupling, p, d);
    if (!x.left || !y.left) continue;
    const double vx = value(x.direction), vy = value(y.direction);
    s1 += vx, s2 += vy, s11 += vx * vx, s22 += vy * vy, s12 += vx * vy;
    ++n;
    same += x.events == y.events;
  }
  const double m1 = s1 / n, m2 = s2 / n;
  const double corr = (s12 / n - m1 * m2) / std::sqrt((s11 / n - m1 * m1) * (s22 / n - m2 * m2));
  std::printf("| %-11s | %4.2f | %5.0f | %5.3f | %5.3f | %5.3f %5.3f |\n", name, sigma_per_m / kSigmaRedPerM,
              r_m * 1000, corr, static_cast<double>(same) / n, m1, m2);
}

}  // namespace

int main(int argc, char** argv) {
  const int pairs = argc > 1 ? std::max(100, std::atoi(argv[1])) : 2000;
  std::printf("%d pairs a row, sigma_2 = %.0f per m, g = %.3f\n\n", pairs, kSigmaRedPerM, kG);
  std::printf("| coupling    | sigma_1/sigma_2 | wall radius mm | correlation | same event | mean values |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const double ratio : {1.3, 1.6, 2.3, 3.6})
    report("scaled", ratio * kSigmaRedPerM, 0.029, Coupling::scaled, pairs);
  report("scaled", 2.3 * kSigmaRedPerM, 1.0, Coupling::scaled, pairs);
  report("wall-frame", 2.3 * kSigmaRedPerM, 0.029, Coupling::wall_frame, pairs);
  report("wall-frame", 2.3 * kSigmaRedPerM, 1.0, Coupling::wall_frame, pairs);
  report("re-keyed", 2.3 * kSigmaRedPerM, 0.029, Coupling::rekeyed, pairs);
  return 0;
}
