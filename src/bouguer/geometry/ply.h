#pragma once
// PLY meshes (ASCII and binary little/big endian): vertex x, y, z and face vertex_indices;
// polygons are fan-triangulated, other elements and properties are read and ignored. Counts,
// indices and coordinates are checked (docs/limits.md) before anything is allocated for them.
#include <filesystem>
#include <string>

#include "bouguer/geometry/mesh.h"

namespace bouguer {

Mesh load_ply(const std::filesystem::path& path, const std::string& what);

}  // namespace bouguer
