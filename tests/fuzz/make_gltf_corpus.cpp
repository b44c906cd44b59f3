// Writes the seed files of tests/fuzz/corpus/gltf/: a few tiny valid assets (.glb, and .gltf with
// its buffer as a base64 data URI; a textured quad with a sampler and tangents; thin-walled glass
// with values clamped into the model; a sparse accessor and a strip), then truncated and corrupted copies. Built beside the
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
// A textured quad with NORMAL, TEXCOORD_0 and TANGENT, its base colour and normal textures (one
// 2 × 2 PNG, embedded) read through a sampler: clamp on s, mirror on t, magFilter NEAREST.
GltfDoc sampled_quad() {
  GltfDoc g;
  const int m = g.material({{"name", "Label"},
                            {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}}},
                            {"normalTexture", {{"index", 0}, {"scale", 0.5}}}});
  const int mesh = g.mesh({{-0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, -0.5, 0}, {-0.5, -0.5, 0}}, {0, 3, 2, 0, 2, 1}, m);
  g.attribute(mesh, "NORMAL", {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, 3);
  g.attribute(mesh, "TEXCOORD_0", {-0.5f, -0.5f, 1.5f, -0.5f, 1.5f, 1.5f, -0.5f, 1.5f}, 2);
  g.attribute(mesh, "TANGENT", {0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, -1, 0, 1, 0, -1}, 4);
  // A 2 × 2 8-bit RGB PNG (IHDR, one IDAT, IEND), its texels four tangent-space normals.
  static const unsigned char png[] = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
      0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x02, 0x00, 0x00, 0x00, 0xfd, 0xd4, 0x9a, 0x73, 0x00, 0x00, 0x00,
      0x15, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x38, 0x91, 0x72, 0xc7, 0x66, 0xdf, 0x33, 0x86, 0x86, 0x86,
      0xff, 0x40, 0x00, 0x00, 0x38, 0x06, 0x08, 0xe5, 0xa3, 0x81, 0xe5, 0xef, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45,
      0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  g.doc["images"] = {{{"bufferView", g.view(png, sizeof png)}, {"mimeType", "image/png"}}};
  g.doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}}};
  g.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
  g.node({{"mesh", mesh}, {"scale", {-1, 1, 1}}});
  return g;
}
// Thin-walled glass (no KHR_materials_volume: a thin dielectric sheet), an emitter, and values
// outside what Bouguer models that load clamped with a warning (ior 0, a base colour above 1, a
// negative strength), with the default scene's studio key.
GltfDoc thin_and_clamped() {
  GltfDoc g;
  const int sheet = g.material({{"name", "Pane"},
                                {"pbrMetallicRoughness", {{"baseColorFactor", {1.2, 0.9, 0.8, 1}}, {"roughnessFactor", 0.4}}},
                                {"extensions",
                                 {{"KHR_materials_transmission", {{"transmissionFactor", 0.7}}},
                                  {"KHR_materials_ior", {{"ior", 0.0}}}}}});
  const int glow = g.material({{"name", "Glow"}, {"emissiveFactor", {1, 0.5, 0.2}},
                               {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", -3.0}}}}}});
  g.doc["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_emissive_strength"};
  g.node({{"mesh", g.mesh(bouguer::test::cube_positions(), bouguer::test::cube_indices(), sheet)}});
  g.node({{"mesh", g.mesh(bouguer::test::cube_positions(), bouguer::test::cube_indices(), glow)}, {"translation", {0, 2, 0}}});
  g.doc["scenes"][0]["extras"] = {{"bouguer_studio", true}};
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
  // Samplers and tangents: the valid quad, a wrap code that is none, and a tangent w of 0.
  sampled_quad().write(dir / "sampler_tangent.glb");
  GltfDoc bad_wrap = sampled_quad();
  bad_wrap.doc["samplers"][0]["wrapT"] = 12345;
  bad_wrap.write(dir / "bad_wrap.glb");
  GltfDoc bad_tangent = sampled_quad();
  const std::size_t at = bad_tangent.doc["bufferViews"][bad_tangent.doc["accessors"][4]["bufferView"].get<std::size_t>()]["byteOffset"];
  const float zero = 0.0f;
  bad_tangent.bin.replace(at + 12, 4, reinterpret_cast<const char*>(&zero), 4);  // the first tangent's w
  bad_tangent.write(dir / "bad_tangent.glb");
  thin_and_clamped().write(dir / "thin_and_clamped.glb");
  // A sparse POSITION accessor: vertex 0 moved by substitution, and a triangle strip.
  GltfDoc sparse = glass_cube();
  const std::uint16_t index = 0;
  const float moved[3] = {-0.6f, -0.6f, -0.6f};
  const int iv = sparse.view(&index, 2), vv = sparse.view(moved, 12);
  sparse.doc["accessors"][0]["sparse"] = {{"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", 5123}}},
                                          {"values", {{"bufferView", vv}}}};
  sparse.doc["accessors"][0]["min"] = {-0.6, -0.6, -0.6};
  sparse.doc["meshes"][1]["primitives"][0]["mode"] = 5;
  sparse.write(dir / "sparse_strip.glb");
  return 0;
}
