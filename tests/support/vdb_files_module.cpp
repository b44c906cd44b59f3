// The tests' OpenVDB files through libbouguer_test_vdb.so (support/vdb_files.h), loaded the first
// time a test writes or samples a grid.
#include <stdexcept>
#include <string>

#include "bouguer/core/module.h"
#include "support/vdb_files.h"

namespace bouguer::test {
namespace {

const VdbFilesApi& api() {
  std::string problem;
  const VdbFilesApi* a = module_api_once<VdbFilesApi>(BOUGUER_TEST_VDB_MODULE, "bouguer_test_vdb_files_api", false,
                                                      problem);
  if (!a) throw std::runtime_error("the tests' OpenVDB module does not load: " + problem);
  return *a;
}

}  // namespace

void write_vdb_file(const std::filesystem::path& path, const std::vector<VdbTestGrid>& grids) {
  api().write(path, grids);
}

void write_vdb_file_with_instance(const std::filesystem::path& path, const VdbTestGrid& grid,
                                  const std::string& instance) {
  api().write_with_instance(path, grid, instance);
}

std::vector<double> openvdb_box_samples(const std::filesystem::path& path, const std::string& name,
                                        const std::vector<Vec3>& points_m) {
  return api().box_samples(path, name, points_m);
}

}  // namespace bouguer::test
