#include "bouguer/render/path_guide.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bouguer {
namespace {

// A unit direction's point in the unit square, and back.
std::array<double, 2> to_square(const Vec3& d) {
  const double cos_theta = std::clamp(d.z, -1.0, 1.0);
  double phi = std::atan2(d.y, d.x);
  if (phi < 0.0) phi += 2.0 * std::numbers::pi;
  return {std::clamp(0.5 * (cos_theta + 1.0), 0.0, 1.0), std::clamp(phi / (2.0 * std::numbers::pi), 0.0, 1.0)};
}

Vec3 from_square(double x, double y) {
  const double cos_theta = 2.0 * x - 1.0;
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * std::numbers::pi * y;
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

// The quadrant of (x, y) in a cell of the unit square, and (x, y) in that quadrant's own square.
int quadrant(double& x, double& y) {
  const int i = (x >= 0.5 ? 1 : 0) | (y >= 0.5 ? 2 : 0);
  x = std::min(2.0 * x - ((i & 1) ? 1.0 : 0.0), 1.0);
  y = std::min(2.0 * y - ((i & 2) ? 1.0 : 0.0), 1.0);
  return i;
}

}  // namespace

DirectionTree::DirectionTree() : nodes_(1) {}

double DirectionTree::total() const { return nodes_[0].total(); }

Vec3 DirectionTree::sample(double u1, double u2, double u3) const {
  double x0 = 0.0, y0 = 0.0, size = 1.0;
  std::uint32_t n = 0;
  for (;;) {
    const auto& sum = nodes_[n].sum;
    const double target = u1 * nodes_[n].total();
    double below = 0.0;
    int last = 3;  // (the last quadrant with light takes what rounding leaves past the others)
    while (last > 0 && !(sum[static_cast<std::size_t>(last)] > 0.0)) --last;
    int i = 0;
    while (i < last && (below + sum[static_cast<std::size_t>(i)] <= target || !(sum[static_cast<std::size_t>(i)] > 0.0)))
      below += sum[static_cast<std::size_t>(i++)];
    const double s = sum[static_cast<std::size_t>(i)];
    u1 = s > 0.0 ? std::clamp((target - below) / s, 0.0, 1.0 - 1e-16) : 0.5;
    size *= 0.5;
    x0 += (i & 1) ? size : 0.0;
    y0 += (i & 2) ? size : 0.0;
    const std::uint32_t c = nodes_[n].child[static_cast<std::size_t>(i)];
    if (c == 0) break;
    n = c;
  }
  return from_square(x0 + u2 * size, y0 + u3 * size);
}

double DirectionTree::pdf(const Vec3& d) const {
  auto [x, y] = to_square(d);
  double p = 1.0;
  std::uint32_t n = 0;
  for (;;) {
    const Node& node = nodes_[n];
    const double t = node.total();
    if (!(t > 0.0)) return 0.0;
    const int i = quadrant(x, y);
    p *= 4.0 * node.sum[static_cast<std::size_t>(i)] / t;
    const std::uint32_t c = node.child[static_cast<std::size_t>(i)];
    if (c == 0 || !(p > 0.0)) break;
    n = c;
  }
  return p / (4.0 * std::numbers::pi);
}

void DirectionTree::add(const Vec3& d, double value) {
  if (!(value > 0.0) || !std::isfinite(value)) return;
  auto [x, y] = to_square(d);
  std::uint32_t n = 0;
  for (;;) {
    const int i = quadrant(x, y);
    nodes_[n].sum[static_cast<std::size_t>(i)] += value;
    const std::uint32_t c = nodes_[n].child[static_cast<std::size_t>(i)];
    if (c == 0) return;
    n = c;
  }
}

// The node of `out` for a cell whose old node is `old` (−1: an old leaf's cell, its `value`
// spread evenly over its quadrants), at `depth`.
std::uint32_t DirectionTree::build_into(DirectionTree& out, int old, double value, int depth, double total,
                                        double rho) const {
  const auto index = static_cast<std::uint32_t>(out.nodes_.size());
  out.nodes_.emplace_back();
  for (std::size_t i = 0; i < 4; ++i) {
    const double v = old >= 0 ? nodes_[static_cast<std::size_t>(old)].sum[i] : 0.25 * value;
    const int below = old >= 0 && nodes_[static_cast<std::size_t>(old)].child[i] != 0
                          ? static_cast<int>(nodes_[static_cast<std::size_t>(old)].child[i])
                          : -1;
    if (depth + 1 < kMaxDepth && v > rho * total) {
      const std::uint32_t c = build_into(out, below, v, depth + 1, total, rho);
      out.nodes_[index].child[i] = c;
    }
  }
  return index;
}

DirectionTree DirectionTree::refined(double rho) const {
  DirectionTree out;
  out.nodes_.clear();
  const double t = total();
  build_into(out, 0, t, 0, t > 0.0 ? t : 1.0, rho);
  return out;
}

PathGuide::PathGuide(const Vec3& centre_m, double half_size_m)
    : lo_(centre_m - Vec3{half_size_m, half_size_m, half_size_m}),
      hi_(centre_m + Vec3{half_size_m, half_size_m, half_size_m}),
      nodes_(1),
      leaves_(1) {}

std::uint32_t PathGuide::leaf_index(const Vec3& point) const {
  Vec3 lo = lo_, hi = hi_;
  std::uint32_t n = 0;
  while (nodes_[n].child[0] != 0) {
    const auto axis = static_cast<std::size_t>(nodes_[n].axis);
    const double mid = 0.5 * (lo[axis] + hi[axis]);
    const bool upper = point[axis] >= mid;
    (upper ? lo : hi)[axis] = mid;
    n = nodes_[n].child[upper ? 1 : 0];
  }
  return nodes_[n].leaf;
}

const DirectionTree* PathGuide::at(const Vec3& point) const {
  const Leaf& leaf = leaves_[leaf_index(point)];
  return leaf.sampling.total() > 0.0 ? &leaf.sampling : nullptr;  // (a new tree's is 0)
}

void PathGuide::add(std::span<const GuideRecord> records) {
  for (const GuideRecord& r : records) {
    const Vec3 p{r.point.x, r.point.y, r.point.z};
    Leaf& leaf = leaves_[leaf_index(p)];
    ++leaf.records;
    leaf.building.add(Vec3{r.direction.x, r.direction.y, r.direction.z}, r.radiance_over_pdf);
  }
}

void PathGuide::end_iteration(int iteration) {
  const double threshold = kSpatialThreshold * std::sqrt(std::pow(2.0, iteration));
  // Halve the leaves that took too many records, each half with a copy of what was learned and
  // half the count, until none does (or the bound on leaves is reached).
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    if (nodes_[n].child[0] != 0) continue;
    Leaf& leaf = leaves_[nodes_[n].leaf];
    if (!(static_cast<double>(leaf.records) > threshold) || leaves_.size() >= kMaxLeaves) continue;
    leaf.records /= 2;
    const int axis = (nodes_[n].axis + 1) % 3;
    const auto a = static_cast<std::uint32_t>(nodes_.size());
    const std::uint32_t keep = nodes_[n].leaf;
    leaves_.push_back(leaves_[keep]);
    nodes_.push_back(Node{{0, 0}, keep, axis});
    nodes_.push_back(Node{{0, 0}, static_cast<std::uint32_t>(leaves_.size() - 1), axis});
    nodes_[n].child = {a, a + 1};
    // (the loop reaches the two new nodes later and halves them again where still too many)
  }
  for (Leaf& leaf : leaves_) {
    leaf.sampling = leaf.building;
    leaf.building = leaf.sampling.refined(kDirectionRho);
    leaf.records = 0;
  }
}

std::size_t PathGuide::bytes() const {
  std::size_t b = nodes_.size() * sizeof(Node) + leaves_.size() * sizeof(Leaf);
  for (const Leaf& leaf : leaves_) b += leaf.sampling.bytes() + leaf.building.bytes();
  return b;
}

}  // namespace bouguer
