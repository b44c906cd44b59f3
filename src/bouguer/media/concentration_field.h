#pragma once
// Concentrations that vary in space (the paper's future work: "solutions with varying
// concentrations according to Beer's law"). A field gives c(x) >= 0, in the unit of the absorber
// it scales (mol/L for a solute, else a factor on σ_a), and the exact integral of c along a ray
// segment, so that with σ_a(x, λ) = Σ_k c_k(x)·ε_k(λ) the optical depth of every wavelength is
// τ(λ) = Σ_k ε_k(λ)·∫c_k ds: one scalar per absorber, no noise, no bias.
//
// The analytic fields depend on s, the signed distance along a unit axis from an origin
// (docs/scene-format.md, "Concentration fields"). Along a ray x(t) = o + t·d, s is linear in t,
// s(t) = s0 + a·t with a = d·axis; each field's integral is a closed form in s, with the limit
// a -> 0 (a ray running across the axis, where c is constant) taken explicitly. A voxel grid
// (GridField) is trilinear between its nodes: along a ray it is a cubic in t inside each cell, so
// its integral is exact too, cell by cell.
#include <array>
#include <cstddef>
#include <memory>
#include <variant>
#include <vector>

#include "bouguer/core/math.h"

namespace bouguer {

// s = (x − origin)·axis, axis of unit length.
struct FieldAxis {
  Vec3 origin_m;
  Vec3 axis{0, 1, 0};
  double s_at(const Vec3& x) const { return dot(x - origin_m, axis); }
};

// c = max(0, c0 + g·s).
struct LinearField {
  FieldAxis frame;
  double value = 0.0;
  double slope_per_m = 0.0;
};

// c = c0·exp(−s/H), the sedimentation profile of a colloid. Below s = −kExponentialFloor·H the
// concentration stays at c0·e^kExponentialFloor (an unbounded exponential is no liquid).
struct ExponentialField {
  FieldAxis frame;
  double value = 0.0;
  double scale_length_m = 1.0;
};
inline constexpr double kExponentialFloor = 40.0;

// c = c0/2·erfc(s/w): a layer poured at s < 0 diffusing upwards, w = 2·sqrt(D·t).
struct DiffusionField {
  FieldAxis frame;
  double value = 0.0;
  double width_m = 1.0;
};

// Piecewise constant: value[i] for upper_s_m[i−1] <= s < upper_s_m[i] (the first from −∞), and
// the last value beyond the last bound. upper_s_m increases; value.size() == upper_s_m.size().
struct LayersField {
  FieldAxis frame;
  std::vector<double> upper_s_m;
  std::vector<double> value;
};

struct ConstantField {
  double value = 0.0;
};

// The values of a voxel grid on the nodes of a lattice, x fastest: node (i, j, k) is the point
// (i, j, k) of index space. The outermost nodes are zero (the reader pads the file's active
// voxels by one), so the trilinear field is continuous and zero outside the lattice. At least 2
// nodes along each axis; every value finite and >= 0.
struct GridValues {
  std::array<int, 3> nodes{};
  std::vector<float> value;
  float max_value = 0.0f;
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(nodes[1]) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(nodes[0]) +
           static_cast<std::size_t>(i);
  }
};

// c(x) = scale · trilinear(values) at index_per_m·x + index_at_origin: a grid read from a file
// (io/vdb.h), placed by its own index-to-world map and the scene's transform (inverted here).
// The values are shared and immutable: a field is copied by value (scaled(), compile), its
// millions of voxels are not.
struct GridField {
  std::shared_ptr<const GridValues> values;
  Mat3 index_per_m = Mat3::identity();
  Vec3 index_at_origin{};
  double scale = 1.0;
  Vec3 index_at(const Vec3& x_m) const { return index_per_m * x_m + index_at_origin; }
};

using ConcentrationField =
    std::variant<ConstantField, LinearField, ExponentialField, DiffusionField, LayersField, GridField>;

// c at a point.
double concentration_at(const ConcentrationField& field, const Vec3& x_m);

// ∫ c(o + t·d) dt over [t0, t1] (t1 >= t0, finite), in concentration × metres; d of unit length.
// Exact up to rounding; never negative, at most kMaxColumnDensity.
double column_density(const ConcentrationField& field, const Vec3& origin_m, const Vec3& direction, double t0,
                      double t1);
inline constexpr double kMaxColumnDensity = 1e30;  // beyond it every absorbing wavelength is dark

// The largest c anywhere (the range check of the scene builder); +∞ for the fields that grow
// without bound: linear with a non-zero slope, exponential (towards −s). A grid: its largest
// node times its scale.
double max_concentration(const ConcentrationField& field);

// The largest c on the segment o + t·d, t in [t0, t1] (finite): a majorant for tracking the
// scattering a density field scales. The analytic fields are monotone in s, so their largest
// value lies at an end; layers take the largest layer the segment reaches; a grid the largest
// corner of the cells the segment crosses (trilinear values never exceed their cell's corners).
double max_concentration_on(const ConcentrationField& field, const Vec3& origin_m, const Vec3& direction, double t0,
                            double t1);

// The field times a factor >= 0 (a medium's density field scaling an absorber's concentration).
ConcentrationField scaled(ConcentrationField field, double factor);

}  // namespace bouguer
