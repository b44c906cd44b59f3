#pragma once
// Piecewise-constant majorants of a density field along a ray segment, for tracking the
// scattering it scales (media/scattering.h): the segment [0, t_max] as pieces in order, each with
// a bound ρ̄ ≥ ρ everywhere on it (pbrt-v4's majorant iterators, Pharr, Jakob & Humphreys 2023,
// ch. 11.4, in spirit).
// - a constant: one piece, its value;
// - a grid (grid_field.h): one piece per cell the ray crosses (the cell walk of its column
//   densities), bounded by the largest of the cell's 8 corner values, since the trilinear value is
//   a convex combination of them; cells whose corners are all zero are pieces with ρ̄ = 0, which a
//   walk crosses without a collision, so a sparse grid costs few null collisions. Nothing outside
//   the lattice, where ρ = 0;
// - the analytic fields: kMajorantPieces equal pieces, each bounded by the field's largest value
//   on it (max_concentration_on: exact for these monotone or layered fields).
#include <optional>

#include "bouguer/media/concentration_field.h"
#include "bouguer/media/grid_field.h"

namespace bouguer {

// The density bound is constant on [t0, t1]; ρ̄ may be 0 (nothing to track there).
struct MajorantSegment {
  double t0 = 0.0, t1 = 0.0;
  double density = 0.0;  // ρ̄
};

// The number of equal pieces of a segment through an analytic field.
inline constexpr int kMajorantPieces = 8;

// The pieces of [0, t_max] (finite) along origin + t·direction, in order: next() gives the next
// one, false once the segment is done. Pieces do not overlap; where none lies, ρ = 0. The field
// must outlive the walk (it is referred to, not copied; a temporary is refused).
class DensityMajorant {
 public:
  DensityMajorant(const ConcentrationField& field, const Vec3& origin_m, const Vec3& direction, double t_max);
  DensityMajorant(ConcentrationField&&, const Vec3&, const Vec3&, double) = delete;
  bool next(MajorantSegment& s);

 private:
  const ConcentrationField* field_;
  Vec3 origin_m_, direction_;
  double t_max_;
  int piece_ = 0, pieces_ = 1;  // the constant and analytic fields
  const GridField* grid_ = nullptr;
  std::optional<GridCellWalk> cells_;  // a grid
};

}  // namespace bouguer
