#pragma once
// The verbs of a voxel grid field (concentration_field.h, GridField), which concentration_field.cpp
// dispatches to. Along a ray x(t) = o + t·d the index-space point is p(t) = p0 + t·e, with
// e = index_per_m·d: the walk through the cells (Amanatides & Woo 1987) and the integrals inside
// them are in t, the world metres of the ray, so no voxel size enters the sum.
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

}  // namespace bouguer
