#include "bouguer/geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <cassert>
#include <cstdint>
#include <vector>

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
  join(dst.tangents, src.tangents);
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  for (const auto& t : src.triangles) dst.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

Mesh flipped(Mesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  for (auto& n : m.normals) n = -n;  // shading normals stay on the geometric normal's side
  for (auto& t : m.tangents) t.sign = -t.sign;
  return m;
}

namespace {

// Open-addressing hash map from a grid cell to the chain of representatives in it (head and tail,
// so a chain keeps insertion order): one flat array, no allocation per cell.
class CellTable {
 public:
  struct Key {
    long long x = 0, y = 0, z = 0;
    bool operator==(const Key&) const = default;
  };
  static constexpr std::uint32_t kNone = 0xffffffffu;

  explicit CellTable(std::size_t expected) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.resize(capacity);
  }
  // The cell's first representative, or kNone.
  std::uint32_t head(const Key& k) const {
    const Slot& s = slots_[find(k)];
    return s.used ? s.head : kNone;
  }
  // Appends representative r to the cell's chain; next[] links a chain.
  void append(const Key& k, std::uint32_t r, std::vector<std::uint32_t>& next) {
    Slot& s = slots_[find(k)];
    if (!s.used) s = {k, r, r, true};
    else next[s.tail] = r, s.tail = r;
  }

 private:
  struct Slot {
    Key key;
    std::uint32_t head = kNone, tail = kNone;
    bool used = false;
  };
  std::size_t find(const Key& k) const {
    const std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9e3779b97f4a7c15ull ^
                            static_cast<std::uint64_t>(k.y) * 0xc2b2ae3d27d4eb4full ^
                            static_cast<std::uint64_t>(k.z) * 0x165667b19e3779f9ull;
    std::size_t i = static_cast<std::size_t>(h ^ (h >> 29)) & (slots_.size() - 1);
    while (slots_[i].used && !(slots_[i].key == k)) i = (i + 1) & (slots_.size() - 1);
    return i;
  }
  std::vector<Slot> slots_;
};

}  // namespace

Mesh welded(const Mesh& m, double tolerance_m, bool keep_attributes) {
  // Grid hashing with cells kCell tolerances wide: a vertex merges with the first earlier
  // representative within the tolerance in its own cell, or in a neighbouring one when it lies
  // within the tolerance of their common face (rarely: so most vertices look in one cell).
  constexpr double kCell = 16.0;
  // Cells beyond ±2^58 (a coordinate far larger than the tolerance) all share the outermost cell;
  // llround of such a value, or of NaN, would be undefined.
  auto scaled = [&](double v) {
    const double q = v / tolerance_m;
    return !std::isnan(q) ? std::clamp(q, -0x1p62, 0x1p62) : 0.0;
  };
  CellTable grid(m.positions.size());
  std::vector<std::uint32_t> next;
  Mesh out;
  std::vector<std::uint32_t> remap(m.positions.size());
  const bool normals = keep_attributes && !m.normals.empty(), uvs = keep_attributes && !m.uvs.empty();
  const bool tangents = keep_attributes && !m.tangents.empty();
  auto same_attributes = [&](std::uint32_t j, std::size_t i) {
    return (!normals || dot(out.normals[j], m.normals[i]) > 1.0 - 1e-12) && (!uvs || out.uvs[j] == m.uvs[i]) &&
           (!tangents || out.tangents[j] == m.tangents[i]);
  };
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3& p = m.positions[i];
    std::array<double, 3> q{};
    std::array<long long, 3> cell{};
    std::array<int, 3> lo{}, hi{};
    for (std::size_t a = 0; a < 3; ++a) {
      q[a] = scaled(p[a]);
      cell[a] = static_cast<long long>(std::floor(q[a] / kCell));
      const double within = q[a] - static_cast<double>(cell[a]) * kCell;  // in [0, kCell)
      lo[a] = within <= 1.0 + 1e-9 ? -1 : 0;
      hi[a] = within >= kCell - 1.0 - 1e-9 ? 1 : 0;
    }
    std::uint32_t found = CellTable::kNone;
    for (int dx = lo[0]; dx <= hi[0] && found == CellTable::kNone; ++dx)
      for (int dy = lo[1]; dy <= hi[1] && found == CellTable::kNone; ++dy)
        for (int dz = lo[2]; dz <= hi[2] && found == CellTable::kNone; ++dz)
          for (std::uint32_t j = grid.head({cell[0] + dx, cell[1] + dy, cell[2] + dz}); j != CellTable::kNone; j = next[j])
            if (length(out.positions[j] - p) <= tolerance_m && same_attributes(j, i)) {
              found = j;
              break;
            }
    if (found == CellTable::kNone) {
      found = static_cast<std::uint32_t>(out.positions.size());
      out.positions.push_back(p);
      if (normals) out.normals.push_back(m.normals[i]);
      if (uvs) out.uvs.push_back(m.uvs[i]);
      if (tangents) out.tangents.push_back(m.tangents[i]);
      next.push_back(CellTable::kNone);
      grid.append({cell[0], cell[1], cell[2]}, found, next);
    }
    remap[i] = found;
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
  // Every directed edge as its undirected key and its direction in the lowest bit, sorted: each
  // undirected edge's uses then lie together, and a closed, consistently wound surface uses each
  // one once in each direction. Vertex indices fit 31 bits: a scene holds at most 2^28 triangles.
  assert(m.positions.size() < (std::size_t{1} << 31));
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * m.triangles.size());
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      edges.push_back((std::uint64_t{std::min(a, b)} << 32) | (std::uint64_t{std::max(a, b)} << 1) | (a < b ? 1u : 0u));
    }
  std::sort(edges.begin(), edges.end());
  std::size_t open = 0, flipped_edges = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t count[2] = {0, 0};
    const std::uint64_t edge = edges[i] >> 1;
    for (; i < edges.size() && edges[i] >> 1 == edge; ++i) ++count[edges[i] & 1u];
    for (int d = 0; d < 2; ++d) {
      if (count[d] > 1) ++flipped_edges;                    // a directed edge used twice
      else if (count[d] == 1 && count[1 - d] == 0) ++open;  // used once, never the other way
    }
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

namespace {
Vec3 segment_offset(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = dot(ab, ab);
  const double t = l2 > 0.0 ? std::clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
  return p - (a + ab * t);
}
}  // namespace

Vec3 triangle_offset(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Vec3 n = cross(ab, ac);
  const double longest2 = std::max(dot(ab, ab), dot(ac, ac));
  if (!(dot(n, n) > 1e-24 * longest2 * longest2)) {  // a segment or a point
    const Vec3 e[3] = {segment_offset(p, a, b), segment_offset(p, b, c), segment_offset(p, c, a)};
    const Vec3* nearest = &e[0];
    for (const Vec3& x : e)
      if (length(x) < length(*nearest)) nearest = &x;
    return *nearest;
  }
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap;  // corner a
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return bp;  // corner b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return ap - ab * (d1 / (d1 - d3));  // edge ab
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return cp;  // corner c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return ap - ac * (d2 / (d2 - d6));  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)  // edge bc
    return bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = va + vb + vc;
  return ap - ab * (vb / denom) - ac * (vc / denom);  // the face
}

double triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return length(triangle_offset(p, a, b, c));
}

}  // namespace bouguer
