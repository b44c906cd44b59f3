// Writes the seed files of tests/fuzz/corpus/gltf/: a few tiny valid assets (.glb, and .gltf with
// its buffer as a base64 data URI), then truncated and corrupted copies. Built beside the
// harnesses (tests/fuzz/CMakeLists.txt):
//   build-fuzz/tests/fuzz/make_gltf_corpus tests/fuzz/corpus/gltf
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "support/gltf_files.h"

namespace fs = std::filesystem;
using bouguer::test::GltfDoc;
using nlohmann::json;

namespace {
std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
void put(const fs::path& p, const std::string& b) { std::ofstream(p, std::ios::binary) << b; }

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    const unsigned n = (unsigned(std::uint8_t(in[i])) << 16) |
                       (i + 1 < in.size() ? unsigned(std::uint8_t(in[i + 1])) << 8 : 0u) |
                       (i + 2 < in.size() ? unsigned(std::uint8_t(in[i + 2])) : 0u);
    out += k[(n >> 18) & 63];
    out += k[(n >> 12) & 63];
    out += i + 1 < in.size() ? k[(n >> 6) & 63] : '=';
    out += i + 2 < in.size() ? k[n & 63] : '=';
  }
  return out;
}

GltfDoc glass_cube() {
  GltfDoc g;
  const int m = g.material({{"name", "Glass"},
                            {"extensions",
                             {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                              {"KHR_materials_volume",
                               {{"thicknessFactor", 0.1}, {"attenuationColor", {0.8, 0.5, 0.3}}, {"attenuationDistance", 0.05}}},
                              {"KHR_materials_ior", {{"ior", 1.5}}},
                              {"KHR_materials_dispersion", {{"dispersion", 0.3}}}}}});
  const int metal = g.material({{"name", "Metal"}, {"pbrMetallicRoughness", {{"metallicFactor", 1.0}, {"roughnessFactor", 0.3}}}});
  const int mesh = g.mesh(bouguer::test::cube_positions(), bouguer::test::cube_indices(), m);
  const int mesh2 = g.mesh(bouguer::test::cube_positions(), bouguer::test::cube_indices(), metal);
  const int child = g.node({{"mesh", mesh2}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 0, 0, 1}}}, false);
  g.doc["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
                             "KHR_materials_dispersion"};
  g.node({{"mesh", mesh}, {"children", {child}}, {"rotation", {0, 0.7071068, 0, 0.7071068}}, {"scale", {0.1, 0.2, 0.1}}});
  return g;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_gltf_corpus DIR\n");
    return 2;
  }
  const fs::path dir = argv[1];
  fs::create_directories(dir);
  glass_cube().write(dir / "glass_cube.glb");
  GltfDoc lit = glass_cube();
  lit.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"aspectRatio", 1.5}, {"znear", 0.01}}}}};
  lit.node({{"camera", 0}, {"translation", {0, 0.1, 1.0}}});
  lit.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "spot"}, {"intensity", 5.0},
                                                              {"spot", {{"outerConeAngle", 0.5}}}}}}}}};
  lit.doc["extensionsUsed"].push_back("KHR_lights_punctual");
  lit.node({{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  lit.write(dir / "camera_and_light.glb");
  // A .gltf with its buffer inside (the harness writes one file).
  GltfDoc e = glass_cube();
  json d = e.doc;
  d["buffers"] = {{{"byteLength", e.bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(e.bin)}}};
  put(dir / "embedded.gltf", d.dump());
  // Broken copies: truncated, and a count past its view.
  const std::string whole = bytes_of(dir / "glass_cube.glb");
  put(dir / "truncated.glb", whole.substr(0, whole.size() / 2));
  json bad = d;
  bad["accessors"][0]["count"] = 1000;
  put(dir / "bad_count.gltf", bad.dump());
  return 0;
}
