#pragma once
// Next-event estimation through a chain of smooth refracting faces of meshes, shading normals
// included: the glass wall of a tumbler, a liquid's surface and the glass above it, a smooth-shaded
// bottle (Hanika, Droske, Fascione 2015's manifold walk). Where manifold.h solves one flat face or
// an exact sphere in closed form, here the path from a vertex x to a point lamp q (or a point drawn
// on an area or spherical lamp) through one to kMaxChain crossings is found by Newton's method on
// the constraints that make each crossing a refraction by the surface's interpolated shading
// normal (the normal the walk refracts by):
//   C_i = the part of η_before·w_back + η_after·w_ahead across the shading normal n_i = 0,
// w_back and w_ahead the unit directions from crossing i to its neighbours (x or the crossing
// before, the next or q). Each crossing moves in its triangle's plane (positions and normals are
// affine there, so the constraints are smooth); after each step the path is traced again from x,
// so every crossing stays on the surface it started on, possibly on a neighbouring triangle.
//
// Contract: solve_chain converges (every |C_i| below 1e-12, in units of the indices) to the path
// whose crossings lie on the same surfaces, in the same order, as the straight segment's from x to
// q, starting from those; or fails. One path per chain: where Snell's law has several (near a
// caustic), the one Newton reaches from the straight line; the others are missed (the docs say so).
#include <array>
#include <cstdint>
#include <optional>
#include <utility>

#include "bouguer/core/math.h"
#include "bouguer/geometry/ray_scene.h"
#include "bouguer/integrators/surface_assembly.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/nested.h"

namespace bouguer {

inline constexpr int kMaxChain = 4;

// One crossing: where the path meets the surface (a mesh triangle: geometry, primitive, point), the
// indices on the side it arrives from and the side it leaves to, the medium beyond and the nested
// set beyond.
struct ChainCrossing {
  Hit hit;
  double eta_from = 1.0, eta_to = 1.0;
  int medium_from = -1, medium_to = -1;
  InsideSet inside_to = 0;
};

// The surface the straight segment from x (on x_hit, or in a medium: null) to q meets first, short
// of q, crossing index-matched ones as a shadow ray does (`inside`: the nested set leaving x), and
// how it is seen there: nothing where none is in the way. Deterministic, so that a walk can ask
// what a connection from x found.
struct FirstSurface {
  Hit hit;
  SurfaceSeen seen;
};
std::optional<FirstSurface> first_surface(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                          const Vec3& q, std::uint64_t& rays);

// The crossings in order from x towards q; `inside_x`: the nested set leaving x.
struct Chain {
  std::array<ChainCrossing, kMaxChain> crossing{};
  int count = 0;
  InsideSet inside_x = 0;
};

// The same crossings walked the other way, from q to x (their sides swapped), for the tube seen
// from q (chain_reverse_tube from q). Its inside_x and each crossing's inside_to stay the forward
// walk's: only the points, the triangles and the indices are read there.
inline Chain reversed(const Chain& c) {
  Chain r = c;
  for (int i = 0; i < c.count; ++i) {
    ChainCrossing& k = r.crossing[static_cast<std::size_t>(i)];
    k = c.crossing[static_cast<std::size_t>(c.count - 1 - i)];
    std::swap(k.eta_from, k.eta_to);
    std::swap(k.medium_from, k.medium_to);
  }
  return r;
}

// The smooth refracting interfaces the straight segment from x to q crosses (short of q, as a
// shadow ray stops: q may be a point on an area lamp's surface), in order (the
// nested set `inside` leaving x; `x_hit` the surface x is on, or null in a medium), crossing
// index-matched ones unchanged. Nothing where something else is in the way (an opaque, rough,
// dispersive or thin surface, an exact shape, a normal map), where there are more than kMaxChain,
// or none.
std::optional<Chain> seed_chain(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside, const Vec3& q,
                                std::uint64_t& rays);

// The same towards a distant lamp: the crossings of the line from x along the unit to_lamp, to
// infinity (nothing where it meets none, or something else).
std::optional<Chain> seed_chain_towards(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                        const Vec3& to_lamp, std::uint64_t& rays);

// Moves the chain's crossings until each refracts by its shading normal (the contract above);
// false where Newton fails (no path near the straight line, total internal reflection, a crossing
// that leaves its surface or a path that meets another first).
bool solve_chain(const RenderScene& s, const Vec3& x, const Hit* x_hit, const Vec3& q, Chain& c, std::uint64_t& rays);

// The same for a distant lamp: the last crossing refracts into the fixed direction to_lamp (its
// constraint's direction ahead is that, wherever the crossing moves).
bool solve_chain_towards(const RenderScene& s, const Vec3& x, const Hit* x_hit, const Vec3& to_lamp, Chain& c,
                         std::uint64_t& rays);

// The shading normal of a mesh triangle at a point of its plane (its vertex normals interpolated
// by the point's barycentrics, as RayScene's hits: the geometric normal without them or where they
// cancel).
Vec3 chain_shading_normal(const RenderScene& s, const Hit& on, const Vec3& point);

// The reverse ray tube of a solved chain: the solid angle of the directions leaving x whose paths
// (refracted at each crossing) pass through a patch at q perpendicular to the last segment, per
// unit area of it, dω_x/dA⊥_q, from the implicit function theorem on the constraints.
double chain_reverse_tube(const RenderScene& s, const Vec3& x, const Vec3& q, const Chain& c);

// A chain solved towards a distant lamp: the cross-section of the lamp's parallel beam (across
// to_lamp, on its side of the last crossing) whose rays, refracted at each crossing, pass through a
// patch at x perpendicular to the first segment, per unit area of it: dA⊥_lamp/dA⊥_x, from the
// implicit function theorem on the constraints with x moving. The irradiance across the beam at x
// is the lamp's E times this (and the crossings' Fresnel and transmittance): flux through a tube,
// no n². Through one plane it is cos θ_l/cos θ_x; through parallel planes the product of theirs.
double chain_beam_tube(const RenderScene& s, const Vec3& x, const Vec3& to_lamp, const Chain& c);

}  // namespace bouguer
