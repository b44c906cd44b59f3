#pragma once
// Nested media by priority (Schmidt & Budge 2002, "Simple Nested Dielectrics in Ray Traced
// Images"): objects with a priority may overlap. A path carries the set of those it is inside
// (one bit each, the bits in order of priority), and the medium at a point is the inside of the
// highest-priority object around it. A surface of an object inside a higher-priority one
// separates nothing (a false intersection, crossed without a vertex); any other surface
// separates the media of the highest-priority objects on its two sides. Plain data and pure
// functions, so the bookkeeping is tested without a scene (tests/unit/test_nested.cpp).
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>

namespace bouguer {

// An object with a priority (RenderScene::nested, sorted by priority, then by order in the scene).
struct NestedObject {
  int priority = 0;
  int inside = -1;   // its medium: an index into RenderScene::media
  int outside = -1;  // the medium around it where it is inside no other nested object
};

// The nested objects a point is inside: bit k for RenderScene::nested[k].
using InsideSet = std::uint64_t;
inline constexpr std::size_t kMaxNestedObjects = 64;
inline constexpr int kMaxPriority = 1000000;  // priorities are whole numbers in [0, kMaxPriority]

inline InsideSet nested_bit(int k) { return InsideSet{1} << static_cast<unsigned>(k); }

// The medium of a point inside the objects of `inside`: the highest one's, `around` in none.
inline int nested_medium(std::span<const NestedObject> nested, InsideSet inside, int around) {
  if (inside == 0) return around;
  return nested[static_cast<std::size_t>(std::bit_width(inside) - 1)].inside;
}

struct NestedSides {
  int front = -1, behind = -1;  // the media in front of a surface (its normal's side) and behind it
};

// The media on the two sides of a surface of nested object k (whose normals point out of it)
// where the path is inside the objects of `inside` (k's own bit is ignored): behind the surface
// it is inside k, in front not. Equal media: a false intersection.
inline NestedSides nested_sides(std::span<const NestedObject> nested, int k, InsideSet inside) {
  const int around = nested[static_cast<std::size_t>(k)].outside;
  return {nested_medium(nested, inside & ~nested_bit(k), around), nested_medium(nested, inside | nested_bit(k), around)};
}

// The set of a path that leaves a surface of nested object k along a direction d with
// d·n = d_dot_n (n its outward normal): inside k behind it, outside in front.
inline InsideSet inside_after(InsideSet inside, int k, double d_dot_n) {
  return d_dot_n < 0.0 ? inside | nested_bit(k) : inside & ~nested_bit(k);
}

}  // namespace bouguer
