#include "support/vdb_files.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

namespace bouguer::test {
namespace {

void initialize_once() {
  static const bool done = [] {
    openvdb::initialize();
    return true;
  }();
  (void)done;
}

openvdb::math::Transform::Ptr transform_of(const VdbTestGrid& g) {
  auto xf = openvdb::math::Transform::createLinearTransform(1.0);
  xf->preScale(openvdb::Vec3d(g.voxel_m.x, g.voxel_m.y, g.voxel_m.z));
  xf->postTranslate(openvdb::Vec3d(g.origin_m.x, g.origin_m.y, g.origin_m.z));
  return xf;
}

template <typename GridT, typename Convert>
typename GridT::Ptr make_grid(const VdbTestGrid& g, Convert convert) {
  auto grid = GridT::create(convert(g.background));
  grid->setName(g.name);
  grid->setTransform(transform_of(g));
  auto accessor = grid->getAccessor();
  for (int k = g.first[2]; k < g.first[2] + g.count[2]; ++k)
    for (int j = g.first[1]; j < g.first[1] + g.count[1]; ++j)
      for (int i = g.first[0]; i < g.first[0] + g.count[0]; ++i) {
        const openvdb::Vec3d x = grid->indexToWorld(openvdb::Coord(i, j, k));
        accessor.setValueOn(openvdb::Coord(i, j, k), convert(static_cast<float>(g.value({x.x(), x.y(), x.z()}))));
      }
  for (const auto& v : g.more) accessor.setValueOn(openvdb::Coord(v[0], v[1], v[2]), convert(1.0f));
  return grid;
}

}  // namespace

void write_vdb_file(const std::filesystem::path& path, const std::vector<VdbTestGrid>& grids) {
  initialize_once();
  openvdb::GridPtrVec out;
  for (const VdbTestGrid& g : grids) {
    if (g.vec3) out.push_back(make_grid<openvdb::Vec3SGrid>(g, [](float v) { return openvdb::Vec3s(v, v, v); }));
    else out.push_back(make_grid<openvdb::FloatGrid>(g, [](float v) { return v; }));
  }
  openvdb::io::File(path.string()).write(out);
}

void write_vdb_file_with_instance(const std::filesystem::path& path, const VdbTestGrid& grid,
                                  const std::string& instance) {
  initialize_once();
  const auto g = make_grid<openvdb::FloatGrid>(grid, [](float v) { return v; });
  const openvdb::GridBase::Ptr copy = g->copyGrid();
  copy->setName(instance);
  openvdb::io::File(path.string()).write(openvdb::GridPtrVec{g, copy});
}

std::vector<double> openvdb_box_samples(const std::filesystem::path& path, const std::string& name,
                                        const std::vector<Vec3>& points_m) {
  initialize_once();
  openvdb::io::File file(path.string());
  file.open(false);
  const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(name));
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(*grid);
  std::vector<double> out;
  for (const Vec3& p : points_m) out.push_back(sampler.wsSample(openvdb::Vec3d(p.x, p.y, p.z)));
  return out;
}

}  // namespace bouguer::test

#ifdef BOUGUER_TEST_VDB_MODULE_BUILD
// The module's one exported symbol (support/vdb_files.h: VdbFilesApi).
// (bouguer_tests exports none of its own symbols, so the module's functions bind to themselves, not
// to the loader's functions of the same names: linking the tests with -rdynamic would change that.
// Hidden visibility for the module crashes OpenVDB, whose headers' statics must be its library's.)
extern "C" const bouguer::test::VdbFilesApi* bouguer_test_vdb_files_api() {
  static const bouguer::test::VdbFilesApi api{1, &bouguer::test::write_vdb_file,
                                              &bouguer::test::write_vdb_file_with_instance,
                                              &bouguer::test::openvdb_box_samples};
  return &api;
}
#endif
