#include "bouguer/io/vdb.h"

#include <fmt/format.h>

#include <array>
#include <fstream>

#include "bouguer/core/memory.h"
#include "bouguer/core/module.h"
#include "bouguer/core/csv.h"
#include "bouguer/core/limits.h"
#include "bouguer/io/vdb_module.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

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
    throw VdbError(fmt::format("{}: not an OpenVDB file (it does not start with the VDB magic number)", path.string()),
                   false);
}

// The module (io/vdb_module.h), loaded once: from where the build put it, else beside the program.
const vdb_module::Api& module_api() {
  std::string problem;
  const auto* api = module_api_once<vdb_module::Api>(BOUGUER_VDB_MODULE, "bouguer_vdb_module_api", false, problem);
  if (!api) throw VdbError(fmt::format("OpenVDB grids cannot be read: {}", problem), false);
  return *api;
}

void raise(const vdb_module::Result& r) {
  if (r.status == vdb_module::Status::ok) return;
  throw VdbError(r.message, r.status == vdb_module::Status::grid_problem);
}

}  // namespace

VdbGrid read_vdb_grid(const fs::path& path, const std::string& grid_name) {
  check_file(path);
  const vdb_module::Api& api = module_api();
  vdb_module::Limits limits;
  limits.max_nodes_per_axis = static_cast<std::uint64_t>(kMaxGridNodesPerAxis);
  limits.max_nodes = kMaxGridNodes;
  limits.memory_available_bytes = [] { return memory_available_bytes(); };
  vdb_module::Grid g;
  const vdb_module::Result r = api.read_grid(path.string(), grid_name, limits, g);
  if (r.status == vdb_module::Status::needs_memory) {
    try {
      require_memory(g.node_count * sizeof(float), r.message, limits.available_bytes);
    } catch (const Error& e) {
      throw VdbError(e.what(), true);
    }
  }
  raise(r);
  VdbGrid out;
  out.values.nodes = g.nodes;
  out.values.value = std::move(g.value);
  out.values.max_value = g.max_value;
  const auto& m = g.world_per_index;
  out.world_per_index = Mat3::from_columns({m[0], m[1], m[2]}, {m[3], m[4], m[5]}, {m[6], m[7], m[8]});
  out.node_origin_m = {g.node_origin_m[0], g.node_origin_m[1], g.node_origin_m[2]};
  return out;
}

std::vector<std::string> vdb_grid_names(const fs::path& path) {
  check_file(path);
  std::vector<std::string> names;
  raise(module_api().grid_names(path.string(), names));
  return names;
}

}  // namespace bouguer
