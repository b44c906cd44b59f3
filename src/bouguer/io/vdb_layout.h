#pragma once
// The layout check of an OpenVDB file, inside the OpenVDB module (libbouguer_vdb.so), run before
// OpenVDB reads the file. OpenVDB trusts the sizes a file states: a string's length, a metadata
// value's size, a zip or blosc chunk's 64-bit compressed size, the counts of root tiles and
// children. It allocates what they ask before it reads (a 5 KB file asked for 140 TB). This walk
// reads the same fields in the same order as OpenVDB 10's io::File (header, file metadata, grid
// descriptors; with `grids`, each grid's metadata, transform, float topology and leaf buffers),
// seeks over the bulk, and checks every size against the bytes that remain, every blosc header's
// nbytes and cbytes against the chunk, and every chunk against the values its node holds. So no
// size that reaches OpenVDB's allocations exceeds the file. It is strict: a layout that OpenVDB's
// writer does not produce is refused rather than guessed at.
#include <string>

#include "bouguer/io/vdb_module.h"

namespace bouguer::vdb_layout {

// ok, or a file_problem (grid_problem for a non-linear map) whose one-line message names the file,
// the field and its byte offset. Needs openvdb::initialize() first (its metadata registry).
vdb_module::Result check(const std::string& path, bool grids);

}  // namespace bouguer::vdb_layout
