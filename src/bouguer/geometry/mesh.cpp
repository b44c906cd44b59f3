#include "bouguer/geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

namespace bouguer {

void append(Mesh& dst, const Mesh& src) {
  const auto base = static_cast<std::uint32_t>(dst.positions.size());
  const bool first = dst.positions.empty();
  auto join = [&](auto& a, const auto& b) {
    if (first) a = b;
    else if (!a.empty() && !b.empty()) a.insert(a.end(), b.begin(), b.end());
    else a.clear();
  };
  join(dst.normals, src.normals);
  join(dst.uvs, src.uvs);
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  for (const auto& t : src.triangles) dst.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

Mesh flipped(Mesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  for (auto& n : m.normals) n = -n;  // shading normals stay on the geometric normal's side
  return m;
}

Mesh welded(const Mesh& m, double tolerance_m) {
  // Grid hashing: a vertex merges with an earlier one in its own or a neighbouring cell.
  struct Key {
    long long x, y, z;
    bool operator<(const Key& o) const { return std::tie(x, y, z) < std::tie(o.x, o.y, o.z); }
  };
  // Cells beyond ±2^62 (a coordinate far larger than the tolerance) all share the outermost cell;
  // llround of such a value, or of NaN, would be undefined.
  auto index = [&](double v) {
    const double q = v / tolerance_m;
    return !std::isnan(q) ? std::llround(std::clamp(q, -0x1p62, 0x1p62)) : 0LL;
  };
  auto cell = [&](const Vec3& p) { return Key{index(p.x), index(p.y), index(p.z)}; };
  std::map<Key, std::vector<std::uint32_t>> grid;
  Mesh out;
  std::vector<std::uint32_t> remap(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3& p = m.positions[i];
    const Key k = cell(p);
    std::optional<std::uint32_t> found;
    for (long long dx = -1; dx <= 1 && !found; ++dx)
      for (long long dy = -1; dy <= 1 && !found; ++dy)
        for (long long dz = -1; dz <= 1 && !found; ++dz) {
          const auto it = grid.find({k.x + dx, k.y + dy, k.z + dz});
          if (it == grid.end()) continue;
          for (const std::uint32_t j : it->second)
            if (length(out.positions[j] - p) <= tolerance_m) {
              found = j;
              break;
            }
        }
    if (!found) {
      found = static_cast<std::uint32_t>(out.positions.size());
      out.positions.push_back(p);
      grid[k].push_back(*found);
    }
    remap[i] = *found;
  }
  for (const auto& t : m.triangles) {
    const std::array<std::uint32_t, 3> r = {remap[t[0]], remap[t[1]], remap[t[2]]};
    if (r[0] != r[1] && r[1] != r[2] && r[0] != r[2]) out.triangles.push_back(r);
  }
  return out;
}

double signed_volume(const Mesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles)
    v += dot(m.positions[t[0]], cross(m.positions[t[1]], m.positions[t[2]]));
  return v / 6.0;
}

std::optional<std::string> closed_surface_problem(const Mesh& m) {
  if (m.triangles.empty()) return "it has no triangles";
  std::unordered_map<std::uint64_t, int> directed;
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; };
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e) ++directed[key(t[e], t[(e + 1) % 3])];
  std::size_t open = 0, flipped_edges = 0;
  for (const auto& [k, count] : directed) {
    const auto a = static_cast<std::uint32_t>(k >> 32), b = static_cast<std::uint32_t>(k & 0xffffffffu);
    if (count > 1) ++flipped_edges;
    else if (!directed.contains(key(b, a))) ++open;
  }
  if (open > 0) return fmt::format("the surface is open ({} boundary edges); an interface must be closed", open);
  if (flipped_edges > 0)
    return fmt::format("{} edges are shared by faces of opposite orientation or by more than two faces", flipped_edges);
  if (signed_volume(m) <= 0.0) return "its faces point inward (negative enclosed volume); reverse the winding";
  return std::nullopt;
}

double max_extent(const Mesh& m) {
  double e = 0.0;
  for (const Vec3& p : m.positions) e = std::max({e, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  return e;
}

}  // namespace bouguer
