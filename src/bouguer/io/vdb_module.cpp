// The OpenVDB module (io/vdb_module.h): reading a float grid into dense node values. Built as
// libbouguer_vdb.so and loaded on first use; it reports problems as messages, never as exceptions
// of the library's types (it shares no code with it).
#include "bouguer/io/vdb_module.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <openvdb/openvdb.h>

#include "bouguer/io/vdb_layout.h"

#include <algorithm>
#include <cmath>
#include <new>

namespace {

using bouguer::vdb_module::Grid;
using bouguer::vdb_module::Limits;
using bouguer::vdb_module::Result;
using bouguer::vdb_module::Status;

// Thrown inside the module only, caught at its edge.
struct Problem {
  Result result;
};

template <typename... Args>
[[noreturn]] void fail_file(fmt::format_string<Args...> f, Args&&... args) {
  throw Problem{{Status::file_problem, fmt::format(f, std::forward<Args>(args)...)}};
}
template <typename... Args>
[[noreturn]] void fail_grid(fmt::format_string<Args...> f, Args&&... args) {
  throw Problem{{Status::grid_problem, fmt::format(f, std::forward<Args>(args)...)}};
}

void initialize_once() {
  static const bool initialized = [] {
    openvdb::initialize();
    return true;
  }();
  (void)initialized;
}

// Runs `body` on the opened file (checked by the library before: io/vdb.cpp, and its layout here:
// io/vdb_layout.h, the grids' too with `grids`), turning everything OpenVDB throws into a file
// problem.
template <typename Body>
Result with_file(const std::string& path, bool grids, Body body) {
  try {
    initialize_once();
    if (Result layout = bouguer::vdb_layout::check(path, grids); layout.status != Status::ok) return layout;
    openvdb::io::File file(path);
    file.open(false);  // no delayed loading: the file is read now, not mapped for later
    body(file);
    return {};
  } catch (const Problem& p) {
    return p.result;
  } catch (const std::bad_alloc&) {
    return {Status::file_problem, fmt::format("{}: OpenVDB ran out of memory reading it (is the file damaged?)", path)};
  } catch (const std::exception& e) {
    return {Status::file_problem, fmt::format("{}: OpenVDB cannot read it: {}", path, e.what())};
  }
}

std::vector<std::string> names_in(openvdb::io::File& file) {
  std::vector<std::string> names;
  for (auto it = file.beginName(); it != file.endName(); ++it) names.push_back(it.gridName());
  return names;
}

std::size_t index(const Grid& g, int i, int j, int k) {
  return (static_cast<std::size_t>(k) * static_cast<std::size_t>(g.nodes[1]) + static_cast<std::size_t>(j)) *
             static_cast<std::size_t>(g.nodes[0]) +
         static_cast<std::size_t>(i);
}

// The lattice of the active bounding box with a border of one node; false when its copy needs
// more memory than there is (g.node_count says how much).
bool lattice_of(const openvdb::CoordBBox& box, Limits& limits, const std::string& what, Grid& g) {
  std::uint64_t total = 1;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t n = std::int64_t{box.max()[k]} - std::int64_t{box.min()[k]} + 3;
    if (static_cast<std::uint64_t>(n) > limits.max_nodes_per_axis)
      fail_grid("{}: {} nodes along an axis, more than {} (docs/limits.md)", what, n, limits.max_nodes_per_axis);
    g.nodes[static_cast<std::size_t>(k)] = static_cast<int>(n);
    total *= static_cast<std::uint64_t>(n);
  }
  if (total > limits.max_nodes)
    fail_grid("{}: its active voxels span {}×{}×{} voxels with the border, more than {} (docs/limits.md)", what,
              g.nodes[0], g.nodes[1], g.nodes[2], limits.max_nodes);
  g.node_count = total;
  limits.available_bytes = limits.memory_available_bytes();
  return total * sizeof(float) <= limits.available_bytes;
}

// Every voxel of the bounding box (active or not, as OpenVDB's samplers read them), with a border
// of zeros.
void dense_values(const openvdb::FloatGrid& grid, const openvdb::Coord& first, const std::string& what, Grid& g) {
  g.value.assign(static_cast<std::size_t>(g.node_count), 0.0f);
  auto accessor = grid.getConstAccessor();
  for (int k = 1; k + 1 < g.nodes[2]; ++k)
    for (int j = 1; j + 1 < g.nodes[1]; ++j)
      for (int i = 1; i + 1 < g.nodes[0]; ++i) {
        const openvdb::Coord ijk = first.offsetBy(i - 1, j - 1, k - 1);
        const float v = accessor.getValue(ijk);
        if (!std::isfinite(v)) fail_grid("{}: voxel ({}, {}, {}) is {}", what, ijk.x(), ijk.y(), ijk.z(), v);
        if (v < 0.0f) fail_grid("{}: voxel ({}, {}, {}) is negative ({}); a concentration is not", what, ijk.x(), ijk.y(), ijk.z(), v);
        g.value[index(g, i, j, k)] = v;
        g.max_value = std::max(g.max_value, v);
      }
}

Result grid_names(const std::string& path, std::vector<std::string>& names) {
  return with_file(path, false, [&](openvdb::io::File& file) { names = names_in(file); });
}

Result read_grid(const std::string& path, const std::string& grid_name, Limits& limits, Grid& out) {
  const std::string what = fmt::format("{}: grid '{}'", path, grid_name);
  Result memory;
  Result r = with_file(path, true, [&](openvdb::io::File& file) {
    const std::vector<std::string> names = names_in(file);
    if (std::find(names.begin(), names.end(), grid_name) == names.end()) {
      if (names.empty()) fail_grid("{}: the file has no grids", path);
      fail_grid("{}: no grid named '{}' (the file has: {})", path, grid_name, fmt::join(names, ", "));
    }
    // The type from the grid's header, before its voxels are read.
    const openvdb::GridBase::Ptr header = file.readGridMetadata(grid_name);
    if (header->valueType() != "float")
      fail_grid("{}: holds {} values; a concentration grid holds floats", what, header->valueType());
    const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(grid_name));
    if (!grid) fail_grid("{}: is not a float grid", what);
    if (grid->background() != 0.0f)
      fail_grid("{}: its background is {}; the field is zero outside the active voxels, so it must be 0", what,
                grid->background());
    const openvdb::math::Transform& xf = grid->transform();
    if (!xf.isLinear()) fail_grid("{}: its index-to-world map ({}) is not linear", what, xf.mapType());
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (box.empty()) fail_grid("{}: the grid has no active voxels", what);
    if (!lattice_of(box, limits, what, out)) {
      memory = {Status::needs_memory, what};
      return;
    }
    dense_values(*grid, box.min(), what, out);
    const auto map = xf.baseMap();
    for (int c = 0; c < 3; ++c) {
      const openvdb::Vec3d step = map->applyJacobian(openvdb::Vec3d(c == 0, c == 1, c == 2));
      for (int row = 0; row < 3; ++row) out.world_per_index[static_cast<std::size_t>(3 * c + row)] = step[row];
    }
    const openvdb::Coord first = box.min();
    const openvdb::Vec3d origin = xf.indexToWorld(openvdb::Vec3d(first.x() - 1, first.y() - 1, first.z() - 1));
    out.node_origin_m = {origin.x(), origin.y(), origin.z()};
  });
  return memory.status == Status::needs_memory ? memory : r;
}

const bouguer::vdb_module::Api kApi{1, grid_names, read_grid};

}  // namespace

// Default visibility throughout: OpenVDB keeps static members of its templates (tree type names)
// that must be the library's own, not copies hidden in this module.
extern "C" const bouguer::vdb_module::Api* bouguer_vdb_module_api() {
  return &kApi;
}
