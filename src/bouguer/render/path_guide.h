#pragma once
// Path guiding's learned picture of where light comes from (Müller, Gross, Novák 2017, "Practical
// Path Guiding for Efficient Light-Transport Simulation"): an SD-tree, a binary tree over the
// scene's bounding cube (cells halved along x, y, z in turn) whose every leaf holds a quadtree
// over directions. The path tracer draws a share of its directions from it (integrators/guiding.h
// says how it is trained and mixed with the BSDF, and why scattering events are not guided).
// Why an SD-tree and not a mixture of lobes (Herholz et al. 2019, Open PGL): training is sums
// added into a fixed tree, so a fixed order of the records gives the same tree on any number of
// threads, passes or processes (a mixture's EM fit depends on the order and the batches); a
// quadtree resolves a 5 mm lamp seen through glass to 4⁻²⁰ of the sphere where a few lobes blur
// it; its memory is bounded by the refinement threshold, and drawing a direction is one descent.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "bouguer/core/math.h"

namespace bouguer {

// One direction a training path drew: where, which way it left (unit), and the incident radiance
// it then found, over the density that drew the direction (an estimate of that light integrated
// over the sphere, what a quadtree cell sums).
struct GuideRecord {
  Vec3f point;
  Vec3f direction;
  float radiance_over_pdf = 0.0f;
};

// A quadtree over the square of equal-area coordinates ((cos θ + 1)/2, φ/2π) about +z, so a cell's
// density is uniform per unit solid angle. Each node keeps the sums of its four quadrants
// (quadrant i: i & 1 the upper half in x, i & 2 in y).
class DirectionTree {
 public:
  static constexpr int kMaxDepth = 20;
  DirectionTree();

  double total() const;
  // A direction drawn with density pdf(): u1 chooses the cell, (u2, u3) the point in it. Only on
  // a tree with total() > 0.
  Vec3 sample(double u1, double u2, double u3) const;
  double pdf(const Vec3& d) const;  // per unit solid angle; 0 on a tree with nothing in it
  void add(const Vec3& d, double value);
  // The next iteration's tree: the cells that hold more than `rho` of the total split (the finer
  // where the light is), the others merged; its sums zero.
  DirectionTree refined(double rho) const;
  std::size_t node_count() const { return nodes_.size(); }
  std::size_t bytes() const { return nodes_.size() * sizeof(Node); }

 private:
  struct Node {
    std::array<double, 4> sum{};
    std::array<std::uint32_t, 4> child{};  // 0: the quadrant is a leaf
    double total() const { return sum[0] + sum[1] + sum[2] + sum[3]; }
  };
  std::uint32_t build_into(DirectionTree& out, int old, double value, int depth, double total, double rho) const;
  std::vector<Node> nodes_;
};

// The directions to draw from at one vertex: the learned tree with probability `alpha`, the
// vertex's own BSDF otherwise (one-sample MIS: every direction is weighted by
// the mixture's density, so the estimate stays unbiased whatever the tree learned).
struct DirectionGuide {
  const DirectionTree* tree = nullptr;  // null: unguided
  double alpha = 0.0;
  explicit operator bool() const { return tree != nullptr; }
  // The mixture's density of d, from the vertex's own density of it.
  double mixture_pdf(double vertex_pdf, const Vec3& d) const {
    return tree ? alpha * tree->pdf(d) + (1.0 - alpha) * vertex_pdf : vertex_pdf;
  }
};

// The spatial binary tree and its leaves' direction trees, each leaf with two: the one drawn from
// (what the last iteration learned) and the one being learned.
class PathGuide {
 public:
  // The cube it covers (points outside fall in the nearest cell).
  PathGuide(const Vec3& centre_m, double half_size_m);

  // The tree to draw from at `point`; null where nothing was learned yet.
  const DirectionTree* at(const Vec3& point) const;
  // Records into the trees being learned, in the order given (the order fixes the sums' rounding).
  void add(std::span<const GuideRecord> records);
  // Ends training iteration `iteration` (0 the first): leaves that took more than
  // kSpatialThreshold·√2^iteration records are halved (each half keeps a copy of what was
  // learned), then every leaf draws from what it learned and learns anew on a refined tree.
  void end_iteration(int iteration);

  std::size_t leaf_count() const { return leaves_.size(); }
  std::size_t bytes() const;  // the memory its trees take

  // Müller et al.'s constants: a spatial cell splits past c·√2^k records (their c = 12 000, for
  // renders of about a million pixels; Bouguer's trial renders are a few thousand, so c is 4000),
  // a direction cell past ρ = 1 % of its tree's total.
  static constexpr double kSpatialThreshold = 4000.0;
  static constexpr double kDirectionRho = 0.01;
  static constexpr std::size_t kMaxLeaves = 8192;  // bounds its memory (about 30 MB at most)

 private:
  struct Node {
    std::array<std::uint32_t, 2> child{};  // 0: a leaf
    std::uint32_t leaf = 0;
    int axis = 0;
  };
  struct Leaf {
    DirectionTree sampling, building;
    std::uint64_t records = 0;
  };
  std::uint32_t leaf_index(const Vec3& point) const;
  Vec3 lo_, hi_;
  std::vector<Node> nodes_;
  std::vector<Leaf> leaves_;
};

}  // namespace bouguer
