// Where a large mesh's set-up goes: a closed mesh of about 4 million triangles (a sphere of 2048
// segments, tessellated) written as a binary PLY, then read, welded, checked for closedness, built
// by Embree, and compiled as a whole scene (glass inside it, so compile welds and checks it too).
// Reports the fastest of BENCH_RUNS (default 3) for each step; asserts nothing.
// Usage: bouguer_bench_mesh [segments]   (default 2048: 4.19 M triangles)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>

#include "bouguer/geometry/mesh.h"
#include "bouguer/geometry/ray_scene.h"
#include "bouguer/geometry/shapes.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"

namespace {
using namespace bouguer;

void write_binary_ply(const std::filesystem::path& path, const Mesh& m) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << m.positions.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << m.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& p : m.positions) {
    const float xyz[3] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
  }
  for (const auto& t : m.triangles) {
    const unsigned char three = 3;
    const std::int32_t idx[3] = {static_cast<std::int32_t>(t[0]), static_cast<std::int32_t>(t[1]),
                                 static_cast<std::int32_t>(t[2])};
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
}

double fastest_s(int runs, const std::function<void()>& step) {
  double best = 1e300;
  for (int i = 0; i < runs; ++i) {
    const auto start = std::chrono::steady_clock::now();
    step();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const int segments = argc > 1 ? std::atoi(argv[1]) : 2048;
  const int runs = std::getenv("BENCH_RUNS") ? std::atoi(std::getenv("BENCH_RUNS")) : 3;
  const auto dir = std::filesystem::temp_directory_path() / "bouguer_bench_mesh";
  std::filesystem::create_directories(dir);
  const auto ply = dir / "sphere.ply";
  write_binary_ply(ply, make_shape(SphereShape{0.05, segments, true}, "bench").front().mesh);

  Mesh read, welded_mesh;
  const double read_s = fastest_s(runs, [&] { read = make_shape(MeshShape{ply}, "bench").front().mesh; });
  const double tolerance = 1e-9 * max_extent(read);
  const double weld_s = fastest_s(runs, [&] { welded_mesh = welded(read, tolerance); });
  bool closed = false;
  const double check_s = fastest_s(runs, [&] { closed = !closed_surface_problem(welded_mesh); });
  const double embree_s = fastest_s(runs, [&] {
    RayScene scene;
    scene.add(read);
    scene.commit();
  });
  const std::string json = R"({"camera": {"resolution": [8, 8]}, "media": {"glass": {"ior": 1.5}},
      "objects": [{"name": "scan", "shape": {"type": "mesh", "file": ")" + ply.string() + R"("}, "inside": "glass"}]})";
  const SceneDesc desc = parse_scene(json, dir / "scene.json");
  const double compile_s = fastest_s(runs, [&] { (void)compile(desc); });
  const SceneDesc sphere = parse_scene(R"({"camera": {"resolution": [8, 8]}, "media": {"glass": {"ior": 1.5}},
      "objects": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.05}, "inside": "glass"}]})",
                                       dir / "scene.json");
  const double analytic_s = fastest_s(runs, [&] { (void)compile(sphere); });

  std::printf("| step | seconds |\n|---|---|\n");
  std::printf("| write the PLY (%zu vertices, %zu triangles), not part of set-up | - |\n", read.positions.size(),
              read.triangles.size());
  std::printf("| read (binary PLY) | %.3f |\n", read_s);
  std::printf("| weld (%zu → %zu vertices) | %.3f |\n", read.positions.size(), welded_mesh.positions.size(), weld_s);
  std::printf("| closedness check (%s) | %.3f |\n", closed ? "closed" : "open", check_s);
  std::printf("| Embree build (add + commit) | %.3f |\n", embree_s);
  std::printf("| compile, all of it | %.3f (%.2f× Embree's build) |\n", compile_s, compile_s / embree_s);
  std::printf("| compile of the analytic sphere, for scale | %.4f |\n", analytic_s);
  std::filesystem::remove_all(dir);
  return 0;
}
