#include "bouguer/media/grid_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bouguer {
namespace {

using Corners = std::array<double, 8>;  // c000, c100, c010, c110, c001, c101, c011, c111
using Cell = GridCell;

Corners corners(const GridValues& g, const Cell& c) {
  const std::size_t nx = static_cast<std::size_t>(g.nodes[0]), nxy = nx * static_cast<std::size_t>(g.nodes[1]);
  const float* v = g.value.data() + g.index(c[0], c[1], c[2]);
  return {v[0], v[1], v[nx], v[nx + 1], v[nxy], v[nxy + 1], v[nxy + nx], v[nxy + nx + 1]};
}

// The cell's interpolant at local coordinates u, not clamped to [0, 1]³: a piece of a ray that
// rounding puts a hair outside its cell still integrates that cell's polynomial.
double trilinear(const Corners& c, const Vec3& u) {
  const double x00 = c[0] + (c[1] - c[0]) * u.x, x10 = c[2] + (c[3] - c[2]) * u.x;
  const double x01 = c[4] + (c[5] - c[4]) * u.x, x11 = c[6] + (c[7] - c[6]) * u.x;
  const double y0 = x00 + (x10 - x00) * u.y, y1 = x01 + (x11 - x01) * u.y;
  return y0 + (y1 - y0) * u.z;
}

Vec3 cell_origin(const Cell& c) { return {double(c[0]), double(c[1]), double(c[2])}; }

// Narrows [t0, t1] to where p0 + t·e lies in the lattice [0, n−1]³; false when nothing is left.
bool clip_to_lattice(const GridValues& g, const Vec3& p0, const Vec3& e, double& t0, double& t1) {
  for (int k = 0; k < 3; ++k) {
    const double top = g.nodes[k] - 1;
    if (e[k] == 0.0) {
      if (!(p0[k] >= 0.0 && p0[k] <= top)) return false;
      continue;
    }
    double a = -p0[k] / e[k], b = (top - p0[k]) / e[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return t0 < t1;
}

bool usable(const GridField& f, const Vec3& p0, const Vec3& e) {
  return f.values && std::isfinite(p0.x) && std::isfinite(p0.y) && std::isfinite(p0.z) && std::isfinite(e.x) &&
         std::isfinite(e.y) && std::isfinite(e.z);
}

}  // namespace

GridCellWalk::GridCellWalk(const GridField& f, const Vec3& o, const Vec3& d, double t0, double t1)
    : p0_(f.index_at(o)), e_(f.index_per_m * d) {
  if (!usable(f, p0_, e_) || !clip_to_lattice(*f.values, p0_, e_, t0, t1)) return;  // nothing to cross
  g_ = f.values.get();
  const Vec3 start = p0_ + e_ * t0;
  for (int k = 0; k < 3; ++k) {
    cell_[k] = std::clamp(static_cast<int>(std::floor(start[k])), 0, g_->nodes[k] - 2);
    step_[k] = e_[k] > 0.0 ? 1 : e_[k] < 0.0 ? -1 : 0;
    t_next_[k] = step_[k] ? boundary_time(k) : std::numeric_limits<double>::infinity();
  }
  t_ = t0;
  t1_ = t1;
  steps_left_ = g_->nodes[0] + g_->nodes[1] + g_->nodes[2] + 3;
}

double GridCellWalk::boundary_time(int k) const { return (cell_[k] + (step_[k] > 0 ? 1 : 0) - p0_[k]) / e_[k]; }

bool GridCellWalk::next(GridCell& cell, double& ta, double& tb) {
  while (steps_left_ > 0) {
    --steps_left_;
    const int k = static_cast<int>(std::min_element(t_next_.begin(), t_next_.end()) - t_next_.begin());
    const double t_end = std::min(t_next_[k], t1_), from = t_;
    const GridCell here = cell_;
    if (t_end >= t1_) {
      steps_left_ = 0;
    } else {
      t_ = std::max(t_, t_end);
      cell_[k] += step_[k];
      if (cell_[k] < 0 || cell_[k] > g_->nodes[k] - 2) steps_left_ = 0;
      else t_next_[k] = boundary_time(k);
    }
    if (t_end > from) {
      cell = here;
      ta = from;
      tb = t_end;
      return true;
    }
  }
  return false;
}

double grid_cell_max(const GridField& f, const GridCell& cell) {
  const Corners c = corners(*f.values, cell);
  return f.scale * *std::max_element(c.begin(), c.end());
}

double grid_concentration_at(const GridField& f, const Vec3& x_m) {
  if (!f.values) return 0.0;
  const GridValues& g = *f.values;
  const Vec3 p = f.index_at(x_m);
  Cell cell{};
  for (int k = 0; k < 3; ++k) {
    if (!(p[k] >= 0.0 && p[k] <= g.nodes[k] - 1)) return 0.0;  // outside, or not a number
    cell[k] = std::min(static_cast<int>(p[k]), g.nodes[k] - 2);
  }
  return f.scale * std::max(0.0, trilinear(corners(g, cell), p - cell_origin(cell)));
}

double grid_column_density(const GridField& f, const Vec3& o, const Vec3& d, double t0, double t1) {
  GridCellWalk walk(f, o, d, t0, t1);
  const Vec3 &p0 = walk.p0(), &e = walk.e();
  // Gauss–Legendre, 2 points: exact for polynomials of degree 3, the interpolant along a line.
  const double node = 1.0 / std::sqrt(3.0);
  double sum = 0.0;
  Cell cell{};
  for (double ta = 0.0, tb = 0.0; walk.next(cell, ta, tb);) {
    const double half = 0.5 * (tb - ta), mid = 0.5 * (ta + tb);
    const Corners c = corners(*f.values, cell);
    const Vec3 base = p0 - cell_origin(cell);
    sum += half * (trilinear(c, base + e * (mid - half * node)) + trilinear(c, base + e * (mid + half * node)));
  }
  return f.scale * sum;
}

double grid_max_concentration_on(const GridField& f, const Vec3& o, const Vec3& d, double t0, double t1) {
  if (!usable(f, f.index_at(o), f.index_per_m * d)) return 0.0;
  if (!(t1 > t0)) return grid_concentration_at(f, o + d * t0);
  GridCellWalk walk(f, o, d, t0, t1);
  double peak = 0.0;
  Cell cell{};
  for (double ta = 0.0, tb = 0.0; walk.next(cell, ta, tb);) {
    const Corners c = corners(*f.values, cell);
    peak = std::max(peak, *std::max_element(c.begin(), c.end()));
  }
  return f.scale * peak;
}

}  // namespace bouguer
