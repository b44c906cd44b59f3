#pragma once
// The interface of the OpenVDB module (libbouguer_vdb.so, io/vdb_module.cpp), the only code that
// links OpenVDB. It is loaded with dlopen the first time a scene names a .vdb grid (io/vdb.cpp):
// linked into the program, OpenVDB's thousands of symbols cost every start of `bouguer` about
// 70 ms of dynamic relocation (8 times the whole start without it), which a render of a scene
// without grids should not pay. Plain types only: the module shares no code with the library.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace bouguer::vdb_module {

enum class Status { ok, file_problem, grid_problem, needs_memory };

struct Result {
  Status status = Status::ok;
  std::string message;  // names the file (and the grid) when status is a problem
};

// The dense node values of a grid's active bounding box with a border of zeros (GridValues), and
// its linear index-to-world map.
struct Grid {
  std::array<int, 3> nodes{};
  std::vector<float> value;
  float max_value = 0.0f;
  std::array<double, 9> world_per_index{};  // columns along i, j, k
  std::array<double, 3> node_origin_m{};    // where node (0, 0, 0) sits
  std::uint64_t node_count = 0;              // set with needs_memory too
};

struct Limits {
  std::uint64_t max_nodes_per_axis = 0, max_nodes = 0;
  // Asked just before the copy (after OpenVDB has read the file): needs_memory when the copy
  // would take more. The library's memory_available_bytes (core/memory.h).
  std::uint64_t (*memory_available_bytes)() = nullptr;
  std::uint64_t available_bytes = 0;  // set by the module with needs_memory: what it was told
};

struct Api {
  int version = 1;
  Result (*grid_names)(const std::string& path, std::vector<std::string>& names);
  Result (*read_grid)(const std::string& path, const std::string& grid_name, Limits& limits, Grid& out);
};

}  // namespace bouguer::vdb_module

// The module's one exported symbol.
extern "C" const bouguer::vdb_module::Api* bouguer_vdb_module_api();
