// Writes the seed files of tests/fuzz/corpus/vdb/: a few tiny valid grids, then truncated and
// corrupted copies. Built in the fuzz build (tests/fuzz/CMakeLists.txt):
//   build-fuzz/tests/fuzz/make_vdb_corpus tests/fuzz/corpus/vdb
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "support/vdb_files.h"

namespace fs = std::filesystem;
using bouguer::Vec3;
using bouguer::test::VdbTestGrid;

namespace {
std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
void put(const fs::path& p, const std::string& b) { std::ofstream(p, std::ios::binary) << b; }
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_vdb_corpus DIR\n");
    return 2;
  }
  const fs::path dir = argv[1];
  fs::create_directories(dir);
  VdbTestGrid cube;
  cube.count = {2, 2, 2};
  cube.value = [](const Vec3& x) { return 1.0 + 1000.0 * x.x; };
  bouguer::test::write_vdb_file(dir / "cube_2.vdb", {cube});
  VdbTestGrid offset = cube;
  offset.name = "smoke";
  offset.first = {-3, 5, 1};
  offset.count = {3, 1, 2};
  offset.voxel_m = {0.5e-3, 2e-3, 1e-3};
  offset.origin_m = {0.01, -0.02, 0.0};
  VdbTestGrid velocity = cube;
  velocity.name = "velocity";
  velocity.vec3 = true;
  bouguer::test::write_vdb_file(dir / "two_grids.vdb", {offset, velocity});
  VdbTestGrid sparse = cube;
  sparse.count = {1, 1, 1};
  sparse.more = {{9, 0, 17}};
  bouguer::test::write_vdb_file(dir / "sparse.vdb", {sparse});
  const std::string b = bytes_of(dir / "cube_2.vdb");
  put(dir / "truncated_header.vdb", b.substr(0, 40));
  put(dir / "truncated_half.vdb", b.substr(0, b.size() / 2));
  put(dir / "truncated_last_byte.vdb", b.substr(0, b.size() - 1));
  std::string flipped = b;
  for (std::size_t i = 24; i < flipped.size(); i += 13) flipped[i] = static_cast<char>(flipped[i] ^ 0xff);
  put(dir / "corrupted_bytes.vdb", flipped);
  put(dir / "magic_only.vdb", b.substr(0, 8));
  return 0;
}
