#include "support/gltf_files.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace bouguer::test {
namespace fs = std::filesystem;
using nlohmann::json;

GltfDoc::GltfDoc() {
  doc = {{"asset", {{"version", "2.0"}, {"generator", "bouguer tests"}}},
         {"scene", 0},
         {"scenes", json::array({{{"nodes", json::array()}}})},
         {"nodes", json::array()},
         {"meshes", json::array()},
         {"accessors", json::array()},
         {"bufferViews", json::array()}};
}

int GltfDoc::view(const void* bytes, std::size_t size, std::size_t stride) {
  while (bin.size() % 4) bin.push_back('\0');
  json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}};
  if (stride) v["byteStride"] = stride;
  bin.append(static_cast<const char*>(bytes), size);
  doc["bufferViews"].push_back(v);
  return int(doc["bufferViews"].size() - 1);
}

int GltfDoc::positions(const std::vector<Vec3>& p) {
  std::vector<float> f;
  Vec3 lo{1e30, 1e30, 1e30}, hi{-1e30, -1e30, -1e30};
  for (const Vec3& v : p) {
    f.insert(f.end(), {float(v.x), float(v.y), float(v.z)});
    lo = {std::min(lo.x, double(float(v.x))), std::min(lo.y, double(float(v.y))), std::min(lo.z, double(float(v.z)))};
    hi = {std::max(hi.x, double(float(v.x))), std::max(hi.y, double(float(v.y))), std::max(hi.z, double(float(v.z)))};
  }
  const int v = view(f.data(), f.size() * sizeof(float));
  doc["bufferViews"][std::size_t(v)]["target"] = 34962;
  doc["accessors"].push_back({{"bufferView", v}, {"componentType", 5126}, {"count", p.size()}, {"type", "VEC3"},
                              {"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}});
  return int(doc["accessors"].size() - 1);
}

int GltfDoc::indices(const std::vector<std::uint32_t>& i) {
  const int v = view(i.data(), i.size() * sizeof(std::uint32_t));
  doc["bufferViews"][std::size_t(v)]["target"] = 34963;
  doc["accessors"].push_back({{"bufferView", v}, {"componentType", 5125}, {"count", i.size()}, {"type", "SCALAR"}});
  return int(doc["accessors"].size() - 1);
}

int GltfDoc::attribute(int mesh, const std::string& name, const std::vector<float>& values, int components) {
  const int v = view(values.data(), values.size() * sizeof(float));
  doc["accessors"].push_back({{"bufferView", v}, {"componentType", 5126},
                              {"count", values.size() / std::size_t(components)},
                              {"type", components == 2 ? "VEC2" : components == 3 ? "VEC3" : "VEC4"}});
  doc["meshes"][std::size_t(mesh)]["primitives"][0]["attributes"][name] = doc["accessors"].size() - 1;
  return int(doc["accessors"].size() - 1);
}

int GltfDoc::mesh(const std::vector<Vec3>& p, const std::vector<std::uint32_t>& i, int material) {
  json prim = {{"attributes", {{"POSITION", positions(p)}}}, {"indices", indices(i)}};
  if (material >= 0) prim["material"] = material;
  doc["meshes"].push_back({{"primitives", json::array({prim})}});
  return int(doc["meshes"].size() - 1);
}

int GltfDoc::node(json n, bool root) {
  doc["nodes"].push_back(std::move(n));
  const int index = int(doc["nodes"].size() - 1);
  if (root) doc["scenes"][0]["nodes"].push_back(index);
  return index;
}

int GltfDoc::material(json m) {
  if (!doc.contains("materials")) doc["materials"] = json::array();
  doc["materials"].push_back(std::move(m));
  return int(doc["materials"].size() - 1);
}

void GltfDoc::write(const fs::path& path) const {
  json d = doc;
  std::string padded = bin;
  while (padded.size() % 4) padded.push_back('\0');
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (path.extension() == ".glb") {
    d["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string text = d.dump();
    while (text.size() % 4) text.push_back(' ');
    auto u32 = [&](std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67);  // "glTF"
    u32(2);
    u32(std::uint32_t(12 + 8 + text.size() + 8 + padded.size()));
    u32(std::uint32_t(text.size()));
    u32(0x4E4F534A);  // "JSON"
    out << text;
    u32(std::uint32_t(padded.size()));
    u32(0x004E4942);  // "BIN\0"
    out << padded;
  } else {
    const fs::path bin_path = fs::path(path).replace_extension(".bin");
    d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", bin_path.filename().string()}}});
    out << d.dump(1);
    std::ofstream b(bin_path, std::ios::binary | std::ios::trunc);
    b << bin;
  }
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::vector<Vec3> cube_positions() {
  std::vector<Vec3> p;
  for (int i = 0; i < 8; ++i) p.push_back({i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5});
  return p;
}

std::vector<std::uint32_t> cube_indices() {
  // Each face as two counter-clockwise triangles seen from outside.
  return {0, 2, 3, 0, 3, 1,  // -z
          4, 5, 7, 4, 7, 6,  // +z
          0, 1, 5, 0, 5, 4,  // -y
          2, 6, 7, 2, 7, 3,  // +y
          0, 4, 6, 0, 6, 2,  // -x
          1, 3, 7, 1, 7, 5}; // +x
}

}  // namespace bouguer::test
