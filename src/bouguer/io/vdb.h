#pragma once
// OpenVDB files (.vdb): one float grid as the dense values of a grid concentration field
// (media/concentration_field.h, GridField). The only module that includes OpenVDB.
//
// The file is checked before OpenVDB opens it (a regular file within kMaxVdbFileBytes that starts
// with the VDB magic number); every exception OpenVDB throws becomes a VdbError naming the file.
// The grid must hold floats, finite and >= 0, with a background of 0 (the field is zero outside
// its active voxels), a linear index-to-world map, and at most kMaxGridNodes nodes (and the
// memory for them) in the dense copy of its active bounding box.
#include <filesystem>
#include <string>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/core/math.h"
#include "bouguer/media/concentration_field.h"

namespace bouguer {

// A problem with a VDB file: `in_grid` when it concerns the grid asked for (its name, type,
// transform or values) rather than the file as a whole. The message names the file.
class VdbError : public Error {
 public:
  VdbError(const std::string& what, bool in_grid_) : Error(what), in_grid(in_grid_) {}
  bool in_grid;
};

struct VdbGrid {
  GridValues values;                       // with the zero border (GridValues)
  Mat3 world_per_index = Mat3::identity();  // metres per index step: columns along i, j, k
  Vec3 node_origin_m{};                     // where node (0, 0, 0) of `values` sits
};

// The float grid named `grid_name` of the file, in the file's world units (taken as metres).
VdbGrid read_vdb_grid(const std::filesystem::path& path, const std::string& grid_name);

// The names of the file's grids, in file order (the same checks on the file).
std::vector<std::string> vdb_grid_names(const std::filesystem::path& path);

}  // namespace bouguer
