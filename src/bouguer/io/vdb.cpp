#include "bouguer/io/vdb.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>

#include "bouguer/core/memory.h"
#include "bouguer/io/csv.h"
#include "bouguer/io/limits.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

template <typename... Args>
[[noreturn]] void fail_file(fmt::format_string<Args...> f, Args&&... args) {
  throw VdbError(fmt::format(f, std::forward<Args>(args)...), false);
}
template <typename... Args>
[[noreturn]] void fail_grid(fmt::format_string<Args...> f, Args&&... args) {
  throw VdbError(fmt::format(f, std::forward<Args>(args)...), true);
}

// Before OpenVDB sees the file: a regular file of bounded size whose first 8 bytes are the
// magic number (0x56444220, "VDB " as a little-endian int64), so that a scene naming a PNG or a
// folder gets a plain answer instead of whatever OpenVDB makes of it.
void check_file(const fs::path& path) {
  try {
    (void)require_regular_file(path, kMaxVdbFileBytes);
  } catch (const Error& e) {
    throw VdbError(e.what(), false);
  }
  std::array<unsigned char, 8> head{};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  const std::array<unsigned char, 8> magic = {0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0};
  if (in.gcount() != static_cast<std::streamsize>(head.size()) || head != magic)
    fail_file("{}: not an OpenVDB file (it does not start with the VDB magic number)", path.string());
}

void initialize_once() {
  static const bool initialized = [] {
    openvdb::initialize();
    return true;
  }();
  (void)initialized;
}

// Runs `body` on the opened file, turning everything OpenVDB throws into a VdbError.
template <typename Body>
auto with_file(const fs::path& path, Body body) {
  check_file(path);
  initialize_once();
  try {
    openvdb::io::File file(path.string());
    file.open(false);  // no delayed loading: the file is read now, not mapped for later
    return body(file);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail_file("{}: OpenVDB ran out of memory reading it (is the file damaged?)", path.string());
  } catch (const std::exception& e) {
    fail_file("{}: OpenVDB cannot read it: {}", path.string(), e.what());
  }
}

std::vector<std::string> names_in(openvdb::io::File& file) {
  std::vector<std::string> names;
  for (auto it = file.beginName(); it != file.endName(); ++it) names.push_back(it.gridName());
  return names;
}

struct Lattice {
  openvdb::Coord first;                 // the voxel of node (1, 1, 1): node 0 is the zero border
  std::array<int, 3> nodes{};
};

Lattice lattice_of(const openvdb::CoordBBox& box, const std::string& what) {
  Lattice l;
  l.first = box.min();
  std::uint64_t total = 1;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t n = std::int64_t{box.max()[k]} - std::int64_t{box.min()[k]} + 3;
    if (n > kMaxGridNodesPerAxis) fail_grid("{}: {} nodes along an axis, more than {} (docs/limits.md)", what, n, kMaxGridNodesPerAxis);
    l.nodes[k] = static_cast<int>(n);
    total *= static_cast<std::uint64_t>(n);
  }
  if (total > kMaxGridNodes)
    fail_grid("{}: its active voxels span {}×{}×{} voxels with the border, more than {} (docs/limits.md)", what,
              l.nodes[0], l.nodes[1], l.nodes[2], kMaxGridNodes);
  try {
    require_memory(total * sizeof(float), what);
  } catch (const Error& e) {
    throw VdbError(e.what(), true);
  }
  return l;
}

// The dense node values: every voxel of the bounding box (active or not, as OpenVDB's samplers
// read them), with a border of zeros.
GridValues dense_values(const openvdb::FloatGrid& grid, const Lattice& l, const std::string& what) {
  GridValues g;
  g.nodes = l.nodes;
  g.value.assign(static_cast<std::size_t>(l.nodes[0]) * static_cast<std::size_t>(l.nodes[1]) *
                     static_cast<std::size_t>(l.nodes[2]),
                 0.0f);
  auto accessor = grid.getConstAccessor();
  for (int k = 1; k + 1 < l.nodes[2]; ++k)
    for (int j = 1; j + 1 < l.nodes[1]; ++j)
      for (int i = 1; i + 1 < l.nodes[0]; ++i) {
        const openvdb::Coord ijk = l.first.offsetBy(i - 1, j - 1, k - 1);
        const float v = accessor.getValue(ijk);
        if (!std::isfinite(v)) fail_grid("{}: voxel ({}, {}, {}) is {}", what, ijk.x(), ijk.y(), ijk.z(), v);
        if (v < 0.0f) fail_grid("{}: voxel ({}, {}, {}) is negative ({}); a concentration is not", what, ijk.x(), ijk.y(), ijk.z(), v);
        g.value[g.index(i, j, k)] = v;
        g.max_value = std::max(g.max_value, v);
      }
  return g;
}

Vec3 vec3(const openvdb::Vec3d& v) { return {v.x(), v.y(), v.z()}; }

VdbGrid to_grid(const openvdb::FloatGrid& grid, const std::string& what) {
  if (grid.background() != 0.0f)
    fail_grid("{}: its background is {}; the field is zero outside the active voxels, so it must be 0", what,
              grid.background());
  const openvdb::math::Transform& xf = grid.transform();
  if (!xf.isLinear()) fail_grid("{}: its index-to-world map ({}) is not linear", what, xf.mapType());
  const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
  if (box.empty()) fail_grid("{}: the grid has no active voxels", what);
  const Lattice l = lattice_of(box, what);
  VdbGrid out;
  out.values = dense_values(grid, l, what);
  const auto map = xf.baseMap();
  out.world_per_index = Mat3::from_columns(vec3(map->applyJacobian({1, 0, 0})), vec3(map->applyJacobian({0, 1, 0})),
                                           vec3(map->applyJacobian({0, 0, 1})));
  out.node_origin_m = vec3(xf.indexToWorld(openvdb::Vec3d(l.first.x() - 1, l.first.y() - 1, l.first.z() - 1)));
  return out;
}

}  // namespace

VdbGrid read_vdb_grid(const fs::path& path, const std::string& grid_name) {
  const std::string what = fmt::format("{}: grid '{}'", path.string(), grid_name);
  return with_file(path, [&](openvdb::io::File& file) {
    const std::vector<std::string> names = names_in(file);
    if (std::find(names.begin(), names.end(), grid_name) == names.end()) {
      if (names.empty()) fail_grid("{}: the file has no grids", path.string());
      fail_grid("{}: no grid named '{}' (the file has: {})", path.string(), grid_name, fmt::join(names, ", "));
    }
    // The type from the grid's header, before its voxels are read.
    const openvdb::GridBase::Ptr header = file.readGridMetadata(grid_name);
    if (header->valueType() != "float")
      fail_grid("{}: holds {} values; a concentration grid holds floats", what, header->valueType());
    const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(grid_name));
    if (!grid) fail_grid("{}: is not a float grid", what);
    return to_grid(*grid, what);
  });
}

std::vector<std::string> vdb_grid_names(const fs::path& path) {
  return with_file(path, [](openvdb::io::File& file) { return names_in(file); });
}

}  // namespace bouguer
