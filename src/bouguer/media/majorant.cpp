#include "bouguer/media/majorant.h"

namespace bouguer {

DensityMajorant::DensityMajorant(const ConcentrationField& field, const Vec3& origin_m, const Vec3& direction,
                                 double t_max)
    : field_(&field), origin_m_(origin_m), direction_(direction), t_max_(t_max) {
  if (const auto* grid = std::get_if<GridField>(&field)) {
    grid_ = grid;
    cells_.emplace(*grid, origin_m, direction, 0.0, t_max);
  } else if (!std::holds_alternative<ConstantField>(field)) {
    pieces_ = kMajorantPieces;
  }
}

bool DensityMajorant::next(MajorantSegment& s) {
  if (grid_) {
    GridCell cell{};
    if (!cells_->next(cell, s.t0, s.t1)) return false;
    s.density = grid_cell_max(*grid_, cell);
    return true;
  }
  if (piece_ == pieces_) return false;
  const int p = piece_++;
  s.t0 = t_max_ * p / pieces_;
  s.t1 = p + 1 == pieces_ ? t_max_ : t_max_ * (p + 1) / pieces_;
  s.density = max_concentration_on(*field_, origin_m_, direction_, s.t0, s.t1);
  return true;
}

}  // namespace bouguer
