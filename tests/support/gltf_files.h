#pragma once
// glTF 2.0 files written by the tests (a .gltf with its .bin, or a .glb): a small document builder
// over nlohmann::json, so each test states its asset in a few lines and can break any part of it.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bouguer/core/math.h"

namespace bouguer::test {

class GltfDoc {
 public:
  GltfDoc();
  nlohmann::json doc;  // edit freely (materials, nodes, extensions) before writing
  std::string bin;     // the one buffer's bytes

  // A buffer view over `bytes` appended to the buffer (4-byte aligned); returns its index.
  int view(const void* bytes, std::size_t size, std::size_t stride = 0);
  int positions(const std::vector<Vec3>& p);  // float VEC3 with min/max
  int indices(const std::vector<std::uint32_t>& i);  // UNSIGNED_INT SCALAR
  // A float accessor of `components` per element (2 VEC2, 3 VEC3, 4 VEC4) set as attribute `name`
  // (NORMAL, TEXCOORD_0, TANGENT) of the mesh's first primitive; returns the accessor index.
  int attribute(int mesh, const std::string& name, const std::vector<float>& values, int components);
  // A mesh of one triangle primitive; returns the mesh index.
  int mesh(const std::vector<Vec3>& p, const std::vector<std::uint32_t>& i, int material = -1);
  // A node (its JSON: mesh, translation, children, ...), listed in the scene when `root`.
  int node(nlohmann::json n, bool root = true);
  int material(nlohmann::json m);

  // .gltf (the buffer beside it as <stem>.bin) or .glb, by the extension.
  void write(const std::filesystem::path& path) const;
};

// A unit cube centred on the origin: 8 vertices, 12 triangles, faces outward.
std::vector<Vec3> cube_positions();
std::vector<std::uint32_t> cube_indices();

}  // namespace bouguer::test
