#pragma once
// Small OpenVDB files written by the tests themselves (tests/support/vdb_files.cpp, the tests'
// only OpenVDB user besides the program's io/vdb_module.cpp), and OpenVDB's own trilinear sampler as a reference.
// The tests reach them through a module loaded on first use (libbouguer_test_vdb.so,
// support/vdb_files_module.cpp), as the program reaches OpenVDB (io/vdb_module.h): linked into
// bouguer_tests, OpenVDB's symbols cost each of the suite's ~490 test processes about 50 ms of
// dynamic relocation at its start (0.06 s against 0.01 s), most of them in tests that write no grid.
#include <array>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bouguer/core/math.h"

namespace bouguer::test {

struct VdbTestGrid {
  std::string name = "density";
  Vec3 voxel_m{1e-3, 1e-3, 1e-3};   // a scale map (one value: a uniform one)
  Vec3 origin_m{};                  // where voxel (0, 0, 0) sits
  std::array<int, 3> first{0, 0, 0};  // the voxels [first, first + count) are set (active)
  std::array<int, 3> count{4, 4, 4};
  std::vector<std::array<int, 3>> more;  // single voxels set (to 1) besides the box
  std::function<double(const Vec3& x_m)> value = [](const Vec3&) { return 1.0; };  // at each voxel
  float background = 0.0f;
  bool vec3 = false;  // a Vec3f grid (value in every component) instead of a float grid
};

void write_vdb_file(const std::filesystem::path& path, const std::vector<VdbTestGrid>& grids);
// The grid, then an instance of it named `instance` (a copy sharing its tree, as OpenVDB writes it).
void write_vdb_file_with_instance(const std::filesystem::path& path, const VdbTestGrid& grid,
                                  const std::string& instance);

// OpenVDB's BoxSampler (trilinear) of the file's grid at world points.
std::vector<double> openvdb_box_samples(const std::filesystem::path& path, const std::string& grid,
                                        const std::vector<Vec3>& points_m);

// What libbouguer_test_vdb.so exports (its entry point bouguer_test_vdb_files_api): the three
// functions above, as vdb_files.cpp defines them.
struct VdbFilesApi {
  int version = 1;
  void (*write)(const std::filesystem::path&, const std::vector<VdbTestGrid>&);
  void (*write_with_instance)(const std::filesystem::path&, const VdbTestGrid&, const std::string&);
  std::vector<double> (*box_samples)(const std::filesystem::path&, const std::string&, const std::vector<Vec3>&);
};

}  // namespace bouguer::test
