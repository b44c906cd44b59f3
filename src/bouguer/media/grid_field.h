#pragma once
// The verbs of a voxel grid field (concentration_field.h, GridField), which concentration_field.cpp
// dispatches to. Along a ray x(t) = o + t·d the index-space point is p(t) = p0 + t·e, with
// e = index_per_m·d: the walk through the cells (Amanatides & Woo 1987) and the integrals inside
// them are in t, the world metres of the ray, so no voxel size enters the sum.
#include <array>

#include "bouguer/media/concentration_field.h"

namespace bouguer {

// c at a point: trilinear inside the lattice, zero outside.
double grid_concentration_at(const GridField& f, const Vec3& x_m);

// ∫ c dt over [t0, t1] (t1 > t0): each cell's trilinear interpolant is a cubic in t along the
// line, integrated exactly by 2-point Gauss–Legendre on the piece inside the cell.
double grid_column_density(const GridField& f, const Vec3& origin_m, const Vec3& direction, double t0, double t1);

// The largest corner value (times scale) of the cells the segment crosses: a majorant of c there.
double grid_max_concentration_on(const GridField& f, const Vec3& origin_m, const Vec3& direction, double t0,
                                 double t1);

// A cell of the lattice: the one between nodes (i, j, k) and (i + 1, j + 1, k + 1).
using GridCell = std::array<int, 3>;

// scale × the largest of the cell's 8 corner values: a bound of c inside it (a trilinear value is
// a convex combination of the corners).
double grid_cell_max(const GridField& f, const GridCell& cell);

// The cells o + t·d crosses over [t0, t1], in order, each with the piece [ta, tb] of the segment
// inside it (Amanatides & Woo 1987): the one cell walk behind the column densities, the maxima
// and the majorants of tracking (media/majorant.h). Each boundary time is computed from p0 afresh
// (no accumulated increments); the step count is bounded by the cells a line can cross, so
// rounding cannot make it loop. Nothing is crossed outside the lattice, or where the ray is not
// finite. The field's values must outlive the walk (a temporary field is refused).
class GridCellWalk {
 public:
  GridCellWalk(const GridField& f, const Vec3& origin_m, const Vec3& direction, double t0, double t1);
  GridCellWalk(GridField&&, const Vec3&, const Vec3&, double, double) = delete;
  // The next cell with ta < tb; false once the segment is done.
  bool next(GridCell& cell, double& ta, double& tb);
  const Vec3& p0() const { return p0_; }  // the ray's origin in index space
  const Vec3& e() const { return e_; }    // its direction in index space, per metre of t

 private:
  double boundary_time(int k) const;
  const GridValues* g_ = nullptr;
  Vec3 p0_, e_;
  GridCell cell_{}, step_{};
  std::array<double, 3> t_next_{};
  double t_ = 0.0, t1_ = 0.0;
  int steps_left_ = 0;
};

}  // namespace bouguer
