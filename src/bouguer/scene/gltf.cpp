// glTF 2.0 through tinygltf (JSON, GLB chunks, base64 buffers) and Draco; every index, count,
// offset and stride checked here before it is used, since tinygltf checks few of them.
#include "bouguer/scene/gltf.h"

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NOEXCEPTION
#include <draco/compression/decode.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <set>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/core/csv.h"
#include "bouguer/core/limits.h"
#include "bouguer/io/texture_image.h"
#include "bouguer/scene/pbr_material.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;
using tinygltf::Model;
using tinygltf::Value;

// A place in the asset, as a Source for the builder's messages and our own.
struct Place {
  const fs::path* file;
  std::string path;
  Place operator/(const std::string& key) const { return {file, path.empty() ? key : path + "." + key}; }
  Place operator[](std::size_t i) const { return {file, fmt::format("{}[{}]", path, i)}; }
  Source source() const { return {*file, path}; }
  template <typename... Args>
  [[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) const {
    source().fail(f, std::forward<Args>(args)...);
  }
};

// Images embedded in the asset (buffer views, data: URIs), decoded by OpenImageIO as tinygltf
// meets them (without a loader tinygltf refuses every asset with an image), by image index.
// External image files tinygltf leaves alone (TINYGLTF_NO_EXTERNAL_IMAGE): a material that uses
// one reads it (texture()).
using DecodedImages = std::map<int, std::shared_ptr<const TextureImage>>;

bool decode_image(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user) {
  // The extension tells OpenImageIO which reader to try first.
  const std::string name = fmt::format("images[{}]{}", index, image->mimeType == "image/jpeg" ? ".jpg" : ".png");
  try {
    (*static_cast<DecodedImages*>(user))[index] = std::make_shared<const TextureImage>(
        read_texture_image(std::span(bytes, static_cast<std::size_t>(std::max(size, 0))), name));
    return true;
  } catch (const Error& e) {
    *err = e.what();
    return false;
  }
}

// External buffers through the project's checked reader (regular files, bounded size).
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  try {
    const std::string bytes = read_file_bytes(path, kMaxMeshFileBytes);
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const Error& e) {
    *err = e.what();
    return false;
  }
}
bool file_exists(const std::string& path, void*) { return fs::exists(path); }
std::string expand_path(const std::string& path, void*) { return path; }
bool no_writes(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

std::string first_line(const std::string& text) {
  const std::string s = text.substr(0, text.find('\n'));
  return s.empty() ? std::string("the asset could not be parsed") : s;
}

// ---- Draco primitives' indices -------------------------------------------------------------------
// A Draco primitive's faces come from its compressed stream; its `indices` accessor only declares a
// count, and conforming encoders write it without a bufferView. tinygltf 2.7 refuses such an
// accessor before it reads extensions, so the document is handed to it without those primitives'
// `indices` (nothing here reads them). Anything that does not parse is passed through unchanged,
// for tinygltf to refuse with its own message.
bool drop_draco_indices(nlohmann::json& doc) {
  const auto accessors = doc.find("accessors");
  const auto meshes = doc.find("meshes");
  if (accessors == doc.end() || !accessors->is_array() || meshes == doc.end() || !meshes->is_array()) return false;
  bool changed = false;
  for (auto& mesh : *meshes) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (auto& primitive : mesh["primitives"]) {
      if (!primitive.is_object() || !primitive.contains("indices") || !primitive.contains("extensions")) continue;
      const auto& ext = primitive["extensions"];
      if (!ext.is_object() || !ext.contains("KHR_draco_mesh_compression")) continue;
      const auto& index = primitive["indices"];
      if (!index.is_number_unsigned() || index.get<std::uint64_t>() >= accessors->size()) continue;
      const auto& accessor = (*accessors)[index.get<std::size_t>()];
      if (!accessor.is_object() || accessor.contains("bufferView")) continue;
      primitive.erase("indices");
      changed = true;
    }
  }
  return changed;
}

std::uint32_t le32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);  // glTF is little-endian, as is every machine Bouguer builds on
  return v;
}
void put_le32(std::string& b, std::uint32_t v) { b.append(reinterpret_cast<const char*>(&v), 4); }

std::string without_draco_indices_json(const std::string& text) {
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object() || !drop_draco_indices(doc)) return text;
  return doc.dump();
}

// A GLB: 12-byte header, a JSON chunk, then an optional BIN chunk kept byte for byte.
constexpr std::uint32_t kGlbJsonChunk = 0x4E4F534Au;  // "JSON", little-endian

std::string without_draco_indices_glb(const std::string& bytes) {
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0 || le32(bytes, 8) != bytes.size()) return bytes;
  const std::uint32_t json_length = le32(bytes, 12);
  if (le32(bytes, 16) != kGlbJsonChunk || json_length > bytes.size() - 20) return bytes;
  const std::string text = bytes.substr(20, json_length);
  std::string json = without_draco_indices_json(text);
  if (json == text) return bytes;
  json.append((4 - json.size() % 4) % 4, ' ');  // chunks are 4-byte aligned, JSON padded with spaces
  const std::string rest = bytes.substr(20 + std::size_t(json_length));
  std::string out = bytes.substr(0, 8);
  put_le32(out, static_cast<std::uint32_t>(12 + 8 + json.size() + rest.size()));
  put_le32(out, static_cast<std::uint32_t>(json.size()));
  put_le32(out, kGlbJsonChunk);
  out += json;
  out += rest;
  return out;
}

// The JSON of a .gltf, or of a .glb's first chunk; empty where the container is malformed (tinygltf
// then refuses it with its own message).
std::string document_text(const std::string& bytes, bool glb) {
  if (!glb) return bytes;
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0 || le32(bytes, 16) != kGlbJsonChunk) return {};
  const std::uint32_t json_length = le32(bytes, 12);
  return json_length <= bytes.size() - 20 ? bytes.substr(20, json_length) : std::string{};
}

// tinygltf hands an embedded image's bytes to the image loader without checking that its buffer
// view lies inside its buffer (a read past the buffer's end, found by the gltf fuzz harness): such a
// view is refused first, against the buffer's declared byteLength, which tinygltf holds every
// loaded buffer to. Values that are not whole numbers are left for tinygltf to refuse.
void check_image_views(const std::string& text, const fs::path& path) {
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return;
  const auto array = [&](const char* key) {
    return doc.contains(key) && doc[key].is_array() ? doc[key] : nlohmann::json::array();
  };
  const nlohmann::json images = array("images"), views = array("bufferViews"), buffers = array("buffers");
  const auto whole = [](const nlohmann::json& o, const char* key,
                        std::uint64_t fallback) -> std::optional<std::uint64_t> {
    if (!o.is_object() || !o.contains(key)) return fallback;
    return o[key].is_number_unsigned() ? std::optional(o[key].get<std::uint64_t>()) : std::nullopt;
  };
  for (std::size_t i = 0; i < images.size(); ++i) {
    const auto v = whole(images[i], "bufferView", views.size());
    if (!v || *v >= views.size()) continue;
    const nlohmann::json& view = views[*v];
    const auto b = whole(view, "buffer", buffers.size());
    if (!b || *b >= buffers.size()) continue;
    const auto offset = whole(view, "byteOffset", 0), length = whole(view, "byteLength", 0);
    const auto buffer_length = whole(buffers[*b], "byteLength", 0);
    if (!offset || !length || !buffer_length) continue;
    if (*offset >= *buffer_length || *length > *buffer_length - *offset)
      fail("{}: bufferViews[{}]: bytes {} to {} lie beyond buffer {} ({} bytes), where images[{}] is read",
           path.string(), *v, *offset, *offset + *length, *b, *buffer_length, i);
  }
}

Model parse_model(const fs::path& path, DecodedImages& images) {
  const std::string file_bytes = read_file_bytes(path, kMaxMeshFileBytes);
  const bool glb = path.extension() == ".glb";
  check_image_views(document_text(file_bytes, glb), path);
  const std::string bytes = glb ? without_draco_indices_glb(file_bytes) : without_draco_indices_json(file_bytes);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(decode_image, &images);
  loader.SetFsCallbacks({file_exists, expand_path, read_whole_file, no_writes, nullptr});
  loader.SetStoreOriginalJSONForExtrasAndExtensions(false);
  Model model;
  std::string err, warn;
  const std::string base = path.parent_path().string();
  const auto size = static_cast<unsigned int>(bytes.size());
  bool ok = false;
  try {
    ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                           size, base)
             : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base);
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (!ok) fail("{}: {}", path.string(), first_line(err));
  return model;
}

// ---- numbers -------------------------------------------------------------------------------------

double finite(double v, const Place& at) {
  if (!std::isfinite(v)) at.fail("not a finite number ({})", v);
  return v;
}

Vec3 vec3(const std::vector<double>& v, const Place& at, Vec3 fallback) {
  if (v.empty()) return fallback;
  if (v.size() < 3) at.fail("needs 3 numbers (got {})", v.size());
  return {finite(v[0], at[0]), finite(v[1], at[1]), finite(v[2], at[2])};
}

const Value* member(const tinygltf::ExtensionMap& ext, const std::string& name) {
  const auto it = ext.find(name);
  return it == ext.end() ? nullptr : &it->second;
}

std::optional<double> number(const Value& v, const std::string& key, const Place& at) {
  if (!v.IsObject() || !v.Has(key)) return std::nullopt;
  const Value& n = v.Get(key);
  if (!n.IsNumber()) (at / key).fail("expected a number");
  return finite(n.GetNumberAsDouble(), at / key);
}

std::optional<Vec3> number3(const Value& v, const std::string& key, const Place& at) {
  if (!v.IsObject() || !v.Has(key)) return std::nullopt;
  const Value& a = v.Get(key);
  if (!a.IsArray() || a.ArrayLen() != 3) (at / key).fail("expected 3 numbers");
  std::array<double, 3> c{};
  for (int i = 0; i < 3; ++i) {
    if (!a.Get(i).IsNumber()) (at / key)[std::size_t(i)].fail("expected a number");
    c[std::size_t(i)] = finite(a.Get(i).GetNumberAsDouble(), (at / key)[std::size_t(i)]);
  }
  return Vec3{c[0], c[1], c[2]};
}

std::size_t checked_index(int index, std::size_t count, const Place& at, const char* what) {
  if (index < 0 || std::size_t(index) >= count) at.fail("{} {} does not exist (the asset has {})", what, index, count);
  return std::size_t(index);
}

// ---- accessors -----------------------------------------------------------------------------------

std::size_t component_bytes(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

double component(const unsigned char* p, int type, bool normalized) {
  auto read = [&](auto v) {
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return double(read(float{}));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return double(read(std::uint32_t{}));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const double v = read(std::uint16_t{});
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const double v = read(std::uint8_t{});
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const double v = read(std::int16_t{});
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    default: {
      const double v = read(std::int8_t{});
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
  }
}

// A buffer view that `at` names by its "bufferView", checked to lie inside its buffer.
struct CheckedView {
  const tinygltf::BufferView& view;
  std::size_t index;           // into bufferViews
  const unsigned char* bytes;  // its first byte in the buffer
  Place place;                 // bufferViews[index]
};
CheckedView checked_view(const Model& m, int view, const Place& at) {
  const std::size_t vi = checked_index(view, m.bufferViews.size(), at / "bufferView", "bufferView");
  const tinygltf::BufferView& v = m.bufferViews[vi];
  const Place pv = (Place{at.file, ""} / "bufferViews")[vi];
  const std::size_t bi = checked_index(v.buffer, m.buffers.size(), pv / "buffer", "buffer");
  const std::size_t buffer_bytes = m.buffers[bi].data.size();
  if (v.byteOffset > buffer_bytes || v.byteLength > buffer_bytes - v.byteOffset)
    pv.fail("bytes {} to {} lie beyond buffer {} ({} bytes)", v.byteOffset, std::uint64_t(v.byteOffset) + v.byteLength,
            bi, buffer_bytes);
  return {v, vi, m.buffers[bi].data.data() + v.byteOffset, pv};
}

// `bytes` bytes from `offset` into buffer view `view`, checked to lie inside the view and its buffer.
const unsigned char* view_bytes(const Model& m, int view, int offset, std::uint64_t bytes, const Place& at) {
  const CheckedView c = checked_view(m, view, at);
  if (offset < 0 || std::uint64_t(offset) > c.view.byteLength || bytes > c.view.byteLength - std::uint64_t(offset))
    at.fail("{} bytes from offset {} do not fit in bufferView {} ({} bytes)", bytes, offset, c.index, c.view.byteLength);
  return c.bytes + std::size_t(offset);
}

// A sparse accessor's substitutions (glTF 3.6.2.3): `count` strictly increasing indices below the
// accessor's count, each replacing its element by one of the tightly packed values.
void apply_sparse(const Model& m, const tinygltf::Accessor& a, int components, std::vector<double>& out, const Place& pa) {
  const auto& sp = a.sparse;
  const Place ps = pa / "sparse";
  if (sp.count < 1 || std::size_t(sp.count) > a.count)
    (ps / "count").fail("{} is not between 1 and the accessor's count {}", sp.count, a.count);
  const int itype = sp.indices.componentType;
  if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    (ps / "indices" / "componentType").fail("{} is not an index type (5121, 5123, 5125)", itype);
  const std::size_t n = std::size_t(sp.count), isize = component_bytes(itype), csize = component_bytes(a.componentType);
  const std::size_t element = csize * std::size_t(components);
  const unsigned char* indices = view_bytes(m, sp.indices.bufferView, sp.indices.byteOffset, std::uint64_t(n) * isize, ps / "indices");
  const unsigned char* values = view_bytes(m, sp.values.bufferView, sp.values.byteOffset, std::uint64_t(n) * element, ps / "values");
  double previous = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double index = component(indices + i * isize, itype, false);
    if (!(index > previous && index < double(a.count)))
      (ps / "indices").fail("index {} at {} is not increasing or not below the accessor's count {}", index, i, a.count);
    previous = index;
    for (std::size_t c = 0; c < std::size_t(components); ++c)
      out[std::size_t(index) * std::size_t(components) + c] = component(values + i * element + c * csize, a.componentType, a.normalized);
  }
}

// The accessor's elements as `components` numbers each, of one of the allowed component types,
// every byte they read inside its buffer view and buffer; a sparse accessor's substitutions applied.
std::vector<double> read_accessor(const Model& m, int index, int components, std::initializer_list<int> types,
                                  const Place& at) {
  const Place where = Place{at.file, ""} / "accessors";
  const std::size_t ai = checked_index(index, m.accessors.size(), at, "accessor");
  const tinygltf::Accessor& a = m.accessors[ai];
  const Place pa = where[ai];
  if (tinygltf::GetNumComponentsInType(std::uint32_t(a.type)) != components)
    pa.fail("type {} where {} components are needed ({})", a.type, components, at.path);
  if (std::find(types.begin(), types.end(), a.componentType) == types.end())
    (pa / "componentType").fail("{} is not accepted here ({})", a.componentType, at.path);
  if (a.count == 0) (pa / "count").fail("must be at least 1");
  if (a.count > kMaxMeshVertices * 3) (pa / "count").fail("{} exceeds the limit of {}", a.count, kMaxMeshVertices * 3);
  const std::size_t csize = component_bytes(a.componentType);
  const std::size_t element = csize * std::size_t(components);
  std::vector<double> out;
  if (a.bufferView < 0) {  // no buffer view: all zeros (glTF 3.6.2.2), unless sparse says otherwise
    out.assign(a.count * std::size_t(components), 0.0);
    if (a.sparse.isSparse) apply_sparse(m, a, components, out, pa);
    return out;
  }
  const CheckedView checked = checked_view(m, a.bufferView, pa);
  const tinygltf::BufferView& v = checked.view;
  const std::size_t vi = checked.index;
  const Place& pv = checked.place;
  const std::size_t stride = v.byteStride == 0 ? element : v.byteStride;
  if (stride < element) (pv / "byteStride").fail("{} is less than accessors[{}]'s element of {} bytes", stride, ai, element);
  if (a.byteOffset % csize != 0) (pa / "byteOffset").fail("{} is not a multiple of {}", a.byteOffset, csize);
  const std::uint64_t needed = std::uint64_t(a.byteOffset) + std::uint64_t(a.count - 1) * stride + element;
  if (needed > v.byteLength)
    (pa / "count")
        .fail("{} exceeds bufferView {} ({} bytes from offset {} hold {} of stride {})", a.count, vi, v.byteLength,
              a.byteOffset, v.byteLength < a.byteOffset + element ? 0 : (v.byteLength - a.byteOffset - element) / stride + 1,
              stride);
  const unsigned char* base = checked.bytes + a.byteOffset;
  out.resize(a.count * std::size_t(components));
  for (std::size_t i = 0; i < a.count; ++i)
    for (int c = 0; c < components; ++c)
      out[i * std::size_t(components) + std::size_t(c)] =
          component(base + i * stride + std::size_t(c) * csize, a.componentType, a.normalized);
  if (a.sparse.isSparse) apply_sparse(m, a, components, out, pa);
  return out;
}

// ---- transforms ----------------------------------------------------------------------------------

Transform node_transform(const tinygltf::Node& n, const Place& at) {
  Transform t;
  if (!n.matrix.empty()) {
    if (n.matrix.size() != 16) (at / "matrix").fail("needs 16 numbers (got {})", n.matrix.size());
    for (std::size_t i = 0; i < 16; ++i) finite(n.matrix[i], (at / "matrix")[i]);
    for (std::size_t c = 0; c < 3; ++c)
      for (std::size_t r = 0; r < 3; ++r) t.linear.m[r][c] = n.matrix[c * 4 + r];  // column-major
    t.translation = {n.matrix[12], n.matrix[13], n.matrix[14]};
    if (n.matrix[3] != 0 || n.matrix[7] != 0 || n.matrix[11] != 0 || n.matrix[15] != 1)
      (at / "matrix").fail("the last row must be [0, 0, 0, 1]");
  } else {
    const Vec3 s = vec3(n.scale, at / "scale", {1, 1, 1});
    std::array<double, 4> q{0, 0, 0, 1};  // x, y, z, w
    if (!n.rotation.empty()) {
      if (n.rotation.size() != 4) (at / "rotation").fail("needs 4 numbers (got {})", n.rotation.size());
      for (std::size_t i = 0; i < 4; ++i) q[i] = finite(n.rotation[i], (at / "rotation")[i]);
      const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (!(std::abs(norm - 1.0) < 1e-3)) (at / "rotation").fail("must be a unit quaternion (its norm is {})", norm);
      for (double& c : q) c /= norm;
    }
    const auto [x, y, z, w] = q;
    const Mat3 r{{{{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                   {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                   {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}}}};
    t.linear = r * Mat3::diagonal(s);
    t.translation = vec3(n.translation, at / "translation", {0, 0, 0});
  }
  return t;
}

Mat3 transposed(const Mat3& a) {
  Mat3 r;
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) r.m[i][j] = a.m[j][i];
  return r;
}

// ---- meshes --------------------------------------------------------------------------------------

struct Attributes {
  std::vector<double> positions, normals, uvs, tangents, indices;
  bool has_indices = false;
};

Attributes draco_attributes(const Model& m, const Value& ext, const Place& at) {
  const Place pe = at / "extensions" / "KHR_draco_mesh_compression";
  if (!ext.IsObject() || !ext.Get("bufferView").IsInt() || !ext.Get("attributes").IsObject())
    pe.fail("needs 'bufferView' and 'attributes'");
  const std::size_t vi = checked_index(ext.Get("bufferView").Get<int>(), m.bufferViews.size(), pe / "bufferView", "bufferView");
  const tinygltf::BufferView& v = m.bufferViews[vi];
  const std::size_t bi = checked_index(v.buffer, m.buffers.size(), (Place{at.file, ""} / "bufferViews")[vi], "buffer");
  const auto& data = m.buffers[bi].data;
  if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset)
    (Place{at.file, ""} / "bufferViews")[vi].fail("lies beyond buffer {} ({} bytes)", bi, data.size());
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data.data() + v.byteOffset), v.byteLength);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) pe.fail("Draco could not decode it: {}", decoded.status().error_msg_string());
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (mesh->num_points() == 0 || mesh->num_points() > kMaxMeshVertices || mesh->num_faces() > kMaxMeshTriangles)
    pe.fail("{} points and {} faces (the limits are {} and {})", mesh->num_points(), mesh->num_faces(),
            kMaxMeshVertices, kMaxMeshTriangles);
  Attributes out;
  auto attribute = [&](const char* name, int components, std::vector<double>& dst) {
    const Value& id = ext.Get("attributes").Get(name);
    if (!id.IsInt()) return;
    const draco::PointAttribute* a = mesh->GetAttributeByUniqueId(std::uint32_t(id.Get<int>()));
    if (!a || a->num_components() != components)
      (pe / "attributes" / name).fail("no Draco attribute {} of {} components", id.Get<int>(), components);
    dst.resize(std::size_t(mesh->num_points()) * std::size_t(components));
    float value[4] = {};
    for (draco::PointIndex i(0); i < mesh->num_points(); ++i) {
      if (!a->ConvertValue<float>(a->mapped_index(i), std::int8_t(components), value))
        (pe / "attributes" / name).fail("cannot be read as numbers");
      for (int c = 0; c < components; ++c) dst[i.value() * std::size_t(components) + std::size_t(c)] = value[c];
    }
  };
  attribute("POSITION", 3, out.positions);
  if (out.positions.empty()) (pe / "attributes").fail("needs POSITION");
  attribute("NORMAL", 3, out.normals);
  attribute("TEXCOORD_0", 2, out.uvs);
  attribute("TANGENT", 4, out.tangents);
  out.has_indices = true;
  out.indices.reserve(std::size_t(mesh->num_faces()) * 3);
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
    for (int k = 0; k < 3; ++k) out.indices.push_back(double(mesh->face(f)[k].value()));
  return out;
}

Attributes primitive_attributes(const Model& m, const tinygltf::Primitive& p, const Place& at) {
  if (const Value* draco = member(p.extensions, "KHR_draco_mesh_compression")) return draco_attributes(m, *draco, at);
  const auto find = [&](const char* name) {
    const auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
  };
  const int position = find("POSITION");
  if (position < 0) (at / "attributes").fail("needs POSITION");
  Attributes out;
  const Place pa = at / "attributes";
  out.positions = read_accessor(m, position, 3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, pa / "POSITION");
  const std::size_t n = out.positions.size() / 3;
  auto same_count = [&](const std::vector<double>& v, int components, const char* name) {
    if (v.size() != n * std::size_t(components))
      (pa / name).fail("{} elements where POSITION has {}", v.size() / std::size_t(components), n);
  };
  if (const int normal = find("NORMAL"); normal >= 0) {
    out.normals = read_accessor(m, normal, 3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, pa / "NORMAL");
    same_count(out.normals, 3, "NORMAL");
  }
  if (const int uv = find("TEXCOORD_0"); uv >= 0) {
    out.uvs = read_accessor(m, uv, 2,
                            {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                            pa / "TEXCOORD_0");
    same_count(out.uvs, 2, "TEXCOORD_0");
  }
  if (const int tangent = find("TANGENT"); tangent >= 0) {  // glTF 3.7.2.1: VEC4, float only
    out.tangents = read_accessor(m, tangent, 4, {TINYGLTF_COMPONENT_TYPE_FLOAT}, pa / "TANGENT");
    same_count(out.tangents, 4, "TANGENT");
  }
  if (p.indices >= 0) {
    out.has_indices = true;
    out.indices = read_accessor(m, p.indices, 1,
                                {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                                at / "indices");
  }
  return out;
}

// TANGENT (x, y, z, w) per vertex, checked (xyz finite and not zero, w ±1) and carried into the
// asset's frame: xyz by the node's linear part, w times the sign of its determinant (geometry/
// transform.cpp says why).
std::vector<Tangent> vertex_tangents(const std::vector<double>& v, std::size_t n, const Transform& to_asset,
                                     const Place& at) {
  if (v.size() != 4 * n) at.fail("{} elements where POSITION has {}", v.size() / 4, n);
  const double handedness = to_asset.determinant() < 0.0 ? -1.0 : 1.0;
  std::vector<Tangent> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 t{v[4 * i], v[4 * i + 1], v[4 * i + 2]};
    const double w = v[4 * i + 3];
    const Vec3 d = to_asset.linear * t;
    const double l = length(d);
    if (!(l > 0.0 && std::isfinite(l))) at.fail("tangent {} ({}, {}, {}) is zero or not finite", i, t.x, t.y, t.z);
    if (w != 1.0 && w != -1.0) at.fail("tangent {}: w is {}, not the handedness 1 or -1", i, w);
    out[i] = {d / l, w * handedness};
  }
  return out;
}

// A strip's or a fan's indices as a triangle list (glTF 3.7.2.1): strip triangle i is
// (v_i, v_{i+1+i%2}, v_{i+2−i%2}), keeping every triangle's winding; fan triangle i is (v_{i+1}, v_{i+2}, v_0).
std::vector<double> triangle_list(const std::vector<double>& v, bool fan) {
  std::vector<double> out;
  out.reserve(3 * (v.size() - 2));
  for (std::size_t i = 0; i + 2 < v.size(); ++i) {
    if (fan) out.insert(out.end(), {v[i + 1], v[i + 2], v[0]});
    else out.insert(out.end(), {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});
  }
  return out;
}

// The primitive's triangles with the node's transform applied (normals by its inverse transpose).
// Its mode is triangles (4, the default), a strip (5) or a fan (6).
GltfPrimitive make_primitive(const Model& m, const tinygltf::Primitive& p, const Transform& to_asset,
                             const Place& at) {
  Attributes a = primitive_attributes(m, p, at);
  const std::size_t n = a.positions.size() / 3;
  if (n > kMaxMeshVertices) at.fail("{} vertices exceed the limit of {}", n, kMaxMeshVertices);
  if (!a.has_indices) {
    a.indices.resize(n);
    for (std::size_t i = 0; i < n; ++i) a.indices[i] = double(i);
  }
  if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP || p.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    if (a.indices.size() < 3) (at / "indices").fail("{} indices make no triangle", a.indices.size());
    a.indices = triangle_list(a.indices, p.mode == TINYGLTF_MODE_TRIANGLE_FAN);
  }
  if (a.indices.size() % 3 != 0) (at / "indices").fail("{} indices are not whole triangles", a.indices.size());
  GltfPrimitive out;
  out.place = at.path;
  out.material = p.material;
  Mesh& mesh = out.shape.mesh;
  mesh.positions.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 v{a.positions[3 * i], a.positions[3 * i + 1], a.positions[3 * i + 2]};
    if (!(std::abs(v.x) <= kMaxMeshCoordinate && std::abs(v.y) <= kMaxMeshCoordinate &&
          std::abs(v.z) <= kMaxMeshCoordinate))
      (at / "attributes" / "POSITION").fail("vertex {} ({}, {}, {}) is not finite or beyond {}", i, v.x, v.y, v.z,
                                             kMaxMeshCoordinate);
    mesh.positions[i] = to_asset.apply(v);
  }
  const bool mirror = to_asset.determinant() < 0.0;
  mesh.triangles.resize(a.indices.size() / 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const double index = a.indices[3 * t + k];
      if (!(index < double(n)))
        (at / "indices").fail("index {} at {} is out of range (the primitive has {} vertices)", index, 3 * t + k, n);
      mesh.triangles[t][mirror ? 2 - k : k] = std::uint32_t(index);
    }
  if (!a.normals.empty()) {
    const Mat3 normal_matrix = transposed(inverse(to_asset.linear));
    out.shape.normals.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 nn = normal_matrix * Vec3{a.normals[3 * i], a.normals[3 * i + 1], a.normals[3 * i + 2]};
      const double l = length(nn);
      if (!(l > 0.0 && std::isfinite(l))) (at / "attributes" / "NORMAL").fail("normal {} is zero or not finite", i);
      out.shape.normals[i] = nn / l;
    }
  }
  if (!a.tangents.empty()) out.shape.tangents = vertex_tangents(a.tangents, n, to_asset, at / "attributes" / "TANGENT");
  if (a.normals.empty()) out.shape.tangents.clear();  // glTF 3.7.2.1: without normals, tangents are ignored
  if (!a.uvs.empty()) {
    out.shape.uvs.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      // glTF's v runs down the image; Bouguer's up (scene/texture.h).
      out.shape.uvs[i] = {finite(a.uvs[2 * i], at / "attributes" / "TEXCOORD_0"),
                          1.0 - finite(a.uvs[2 * i + 1], at / "attributes" / "TEXCOORD_0")};
    }
  }
  return out;
}

// ---- materials -----------------------------------------------------------------------------------

// What a material's textures need from the asset.
struct TextureSources {
  const Model& model;
  const DecodedImages& decoded;
  const fs::path& file;
};

// KHR_texture_transform of a texture reference (its texCoord is read by texture_coordinates).
UvTransform texture_transform(const tinygltf::ExtensionMap& extensions, const Place& at) {
  UvTransform t;
  const Value* e = member(extensions, "KHR_texture_transform");
  if (!e) return t;
  const Place pt = at / "extensions" / "KHR_texture_transform";
  auto pair = [&](const char* key, std::array<double, 2>& out) {
    if (!e->Has(key)) return;
    const Value& a = e->Get(key);
    if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber())
      (pt / key).fail("expected 2 numbers");
    out = {finite(a.Get(0).GetNumberAsDouble(), pt / key), finite(a.Get(1).GetNumberAsDouble(), pt / key)};
  };
  pair("offset", t.offset);
  pair("scale", t.scale);
  t.rotation_rad = number(*e, "rotation", pt).value_or(0.0);
  return t;
}

// The image of texture `index`: decoded with the asset, or read from its file beside the asset.
std::shared_ptr<const TextureImage> texture_image(const TextureSources& src, int index, const Place& at) {
  const auto& texture = src.model.textures[checked_index(index, src.model.textures.size(), at / "index", "texture")];
  const std::size_t image = checked_index(texture.source, src.model.images.size(), at, "image");
  if (const auto it = src.decoded.find(int(image)); it != src.decoded.end()) return it->second;
  const std::string& uri = src.model.images[image].uri;
  if (uri.empty() || uri.starts_with("data:")) (Place{&src.file, "images"})[image].fail("has no image data");
  try {
    return std::make_shared<const TextureImage>(read_texture_image(src.file.parent_path() / uri));
  } catch (const Error& e) {
    (Place{&src.file, "images"})[image].fail("{}", e.what());
  }
}

// Texture `index`'s sampler (glTF 5.26): wrapS and wrapT as the builder's wrap names, magFilter
// NEAREST. minFilter is not read: every lookup is trilinear over the MIP pyramid (docs/assets.md).
void read_sampler(const Model& m, int index, GltfTexture& out, const Place& at) {
  const int sampler = m.textures[std::size_t(index)].sampler;
  if (sampler < 0) return;  // none: repeat, and filtering as the renderer likes
  const std::size_t si = checked_index(sampler, m.samplers.size(), at, "sampler");
  const tinygltf::Sampler& s = m.samplers[si];
  const Place ps = Place{at.file, "samplers"}[si];
  auto wrap = [&](int code, const char* key) -> std::string {
    switch (code) {
      case TINYGLTF_TEXTURE_WRAP_REPEAT: return "repeat";
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return "clamp";
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return "mirror";
      default:
        (ps / key).fail("{} is not a wrap mode (10497 REPEAT, 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT)", code);
    }
  };
  out.wrap = {wrap(s.wrapS, "wrapS"), wrap(s.wrapT, "wrapT")};
  if (s.magFilter != -1 && s.magFilter != TINYGLTF_TEXTURE_FILTER_NEAREST &&
      s.magFilter != TINYGLTF_TEXTURE_FILTER_LINEAR)
    (ps / "magFilter").fail("{} is not a magnification filter (9728 NEAREST, 9729 LINEAR)", s.magFilter);
  out.nearest_magnification = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
}

// A texture's texels times per-channel factors, clamped to [0, 1]: sRGB-decoded first for colour
// (baseColorTexture), as stored for data (metallicRoughnessTexture).
// The texture coordinate set a texture reference reads: its texCoord, or its KHR_texture_transform's.
double texture_coordinates(const tinygltf::TextureInfo& info, const Place& at) {
  const Value* e = member(info.extensions, "KHR_texture_transform");
  if (!e) return info.texCoord;
  return number(*e, "texCoord", at / "extensions" / "KHR_texture_transform").value_or(info.texCoord);
}

// A texture on another coordinate set than TEXCOORD_0 (the only one read) is left out, and noted.
std::optional<GltfTexture> scaled_texture(const TextureSources& src, const tinygltf::TextureInfo& info,
                                          const Vec3& factor, bool colour, const Place& at,
                                          std::vector<std::string>& notes) {
  if (info.index < 0) return std::nullopt;
  if (const double set = texture_coordinates(info, at); set != 0.0) {
    notes.push_back(fmt::format("{} on TEXCOORD_{:g} left out (only TEXCOORD_0 is read)", at.path.substr(at.path.rfind('.') + 1), set));
    return std::nullopt;
  }
  const auto image = texture_image(src, info.index, at);
  auto linear = std::make_shared<TextureImage>(*image);
  linear->srgb = false;
  for (std::size_t i = 0; i < linear->rgb.size(); ++i) {
    const float v = colour && image->srgb ? srgb_to_linear(image->rgb[i]) : image->rgb[i];
    linear->rgb[i] = std::clamp(v * static_cast<float>(std::array{factor.x, factor.y, factor.z}[i % 3]), 0.0f, 1.0f);
  }
  GltfTexture t{std::move(linear), texture_transform(info.extensions, at), at.path};
  read_sampler(src.model, info.index, t, at / "index");
  return t;
}

// ---- values outside what Bouguer models -----------------------------------------------------------
// An asset is someone else's file: a finite value its specification or extensions allow (or that
// glTF's reference viewers clamp silently) is clamped into what Bouguer models and noted, and the
// material's notes become one warning (docs/assets.md, "Values outside the model"). Structure
// (counts, indices, types, non-finite numbers) stays refused.

// The smallest attenuationColor channel: it keeps 10⁻⁶ over attenuationDistance (0 keeps nothing).
constexpr double kMinAttenuationColour = 1e-6;
// The largest index Bouguer models (media/ior.h: below 5), for ior 0 (infinite) and above.
constexpr double kMaxGltfIor = 4.99;
// A hundredth of the emission limit (core/limits.h), room for a saturated colour's spectrum.
constexpr double kMaxEmissiveStrength = kMaxEmission / 100.0;  // also a light's candela or lux
// A camera's yfov within (0, π), and an aspect ratio that keeps both sides of 480 pixels within 16384.
constexpr double kMinYfovRad = 1e-4, kMaxYfovRad = 3.1, kMinAspect = 480.0 / 16384.0;
constexpr double kMinConeRad = 1e-4;  // a spot light's outer cone

bool emits(const GltfMaterial& m) { return std::max({m.emissive.x, m.emissive.y, m.emissive.z}) * m.emissive_strength > 0.0; }

double clamp_noted(double v, double lo, double hi, const std::string& name, std::vector<std::string>& notes) {
  const double c = std::clamp(v, lo, hi);
  if (c != v) notes.push_back(fmt::format("{} {:g} as {:g}", name, v, c));
  return c;
}

Vec3 clamp_noted(const Vec3& v, double lo, double hi, const std::string& name, std::vector<std::string>& notes) {
  return {clamp_noted(v.x, lo, hi, name + "[0]", notes), clamp_noted(v.y, lo, hi, name + "[1]", notes),
          clamp_noted(v.z, lo, hi, name + "[2]", notes)};
}

// The core factors, before they scale the textures.
void clamp_factors(GltfMaterial& m) {
  m.base_color = clamp_noted(m.base_color, 0.0, 1.0, "baseColorFactor", m.clamped);
  m.metallic = clamp_noted(m.metallic, 0.0, 1.0, "metallicFactor", m.clamped);
  m.roughness = clamp_noted(m.roughness, 0.0, 1.0, "roughnessFactor", m.clamped);
  m.emissive = clamp_noted(m.emissive, 0.0, kMaxEmissiveStrength, "emissiveFactor", m.clamped);
}

// The extensions' values, each where the material's mapping uses it (docs/assets.md).
void clamp_extensions(GltfMaterial& m) {
  auto& notes = m.clamped;
  const double peak = std::max({m.emissive.x, m.emissive.y, m.emissive.z, 1.0});  // factor × strength within the limit
  m.emissive_strength = clamp_noted(m.emissive_strength, 0.0, kMaxEmissiveStrength / peak, "emissiveStrength", notes);
  if (emits(m)) return;  // an emitter: nothing else of it is used
  m.transmission = clamp_noted(m.transmission, 0.0, 1.0, "transmissionFactor", notes);
  if (!(m.transmission > 0.0)) return;
  if (m.transmission < 1.0) notes.push_back(fmt::format("transmissionFactor {:g} as 1 (no blend with a diffuse base)", m.transmission));
  m.thickness = clamp_noted(m.thickness, 0.0, std::numeric_limits<double>::max(), "thicknessFactor", notes);
  if (m.ior == 0.0) {  // KHR_materials_ior: 0 stands for an infinite index
    notes.push_back(fmt::format("ior 0 (infinite) as {:g}", kMaxGltfIor));
    m.ior = kMaxGltfIor;
  }
  m.ior = clamp_noted(m.ior, 1.0, kMaxGltfIor, "ior", notes);
  if (m.thickness == 0.0) {  // thin-walled: a smooth sheet, no volume
    if (m.roughness > 0.0) notes.push_back(fmt::format("roughnessFactor {:g} as 0 (the thin sheet is smooth)", m.roughness));
    m.roughness = 0.0;
    return;
  }
  // V_d = 20/D within Bouguer's Abbe range [5, 200]; with ior 1 there is nothing to disperse.
  m.dispersion = clamp_noted(m.dispersion, 0.0, std::numeric_limits<double>::max(), "dispersion", notes);
  if (m.ior == 1.0) m.dispersion = 0.0;
  else if (m.dispersion > 0.0) m.dispersion = clamp_noted(m.dispersion, 20.0 / 200.0, 20.0 / 5.0, "dispersion", notes);
  if (!m.attenuation_distance_m) return;
  m.attenuation_color = clamp_noted(m.attenuation_color, kMinAttenuationColour, 1.0, "attenuationColor", notes);
  m.attenuation_distance_m =
      clamp_noted(*m.attenuation_distance_m, kMinSceneLengthM, std::numeric_limits<double>::max(), "attenuationDistance", notes);
}

GltfMaterial material(const TextureSources& src, const tinygltf::Material& g, const Place& at) {
  GltfMaterial mat;
  mat.name = g.name;
  const auto& pbr = g.pbrMetallicRoughness;
  const Place pp = at / "pbrMetallicRoughness";
  if (!pbr.baseColorFactor.empty()) mat.base_color = vec3(pbr.baseColorFactor, pp / "baseColorFactor", {1, 1, 1});
  mat.metallic = finite(pbr.metallicFactor, pp / "metallicFactor");
  mat.roughness = finite(pbr.roughnessFactor, pp / "roughnessFactor");
  mat.emissive = vec3(g.emissiveFactor, at / "emissiveFactor", {0, 0, 0});
  clamp_factors(mat);
  mat.base_color_texture = scaled_texture(src, pbr.baseColorTexture, mat.base_color, true, pp / "baseColorTexture", mat.clamped);
  // glTF's layout: G roughness, B metalness (R is occlusion in packed textures, unused).
  mat.metallic_roughness_texture = scaled_texture(src, pbr.metallicRoughnessTexture, {1.0, mat.roughness, mat.metallic},
                                                  false, pp / "metallicRoughnessTexture", mat.clamped);
  mat.emissive_texture = scaled_texture(src, g.emissiveTexture, mat.emissive, true, at / "emissiveTexture", mat.clamped);
  tinygltf::TextureInfo normal;  // the same fields as a TextureInfo, and a scale
  normal.index = g.normalTexture.index;
  normal.texCoord = g.normalTexture.texCoord;
  normal.extensions = g.normalTexture.extensions;
  mat.normal_texture = scaled_texture(src, normal, {1.0, 1.0, 1.0}, false, at / "normalTexture", mat.clamped);
  mat.normal_scale = finite(g.normalTexture.scale, at / "normalTexture" / "scale");
  const Place pe = at / "extensions";
  if (const Value* e = member(g.extensions, "KHR_materials_emissive_strength"))
    mat.emissive_strength = number(*e, "emissiveStrength", pe / "KHR_materials_emissive_strength").value_or(1.0);
  if (const Value* e = member(g.extensions, "KHR_materials_transmission"))
    mat.transmission = number(*e, "transmissionFactor", pe / "KHR_materials_transmission").value_or(0.0);
  if (const Value* e = member(g.extensions, "KHR_materials_ior")) mat.ior = number(*e, "ior", pe / "KHR_materials_ior").value_or(1.5);
  if (const Value* e = member(g.extensions, "KHR_materials_dispersion"))
    mat.dispersion = number(*e, "dispersion", pe / "KHR_materials_dispersion").value_or(0.0);
  if (const Value* e = member(g.extensions, "KHR_materials_volume")) {
    const Place pv = pe / "KHR_materials_volume";
    mat.thickness = number(*e, "thicknessFactor", pv).value_or(0.0);
    mat.attenuation_color = number3(*e, "attenuationColor", pv).value_or(Vec3{1, 1, 1});
    mat.attenuation_distance_m = number(*e, "attenuationDistance", pv);
  }
  clamp_extensions(mat);
  return mat;
}

// ---- the node tree -------------------------------------------------------------------------------

constexpr std::size_t kMaxNodeDepth = 1024;  // the walk recurses: bound its stack

struct Walker {
  const Model& m;
  const fs::path& file;
  GltfAsset& out;
  std::vector<bool> visited;
  std::uint64_t triangles = 0;

  Place place(const char* what, std::size_t i) const { return (Place{&file, ""} / what)[i]; }

  void node(std::size_t index, const Transform& parent, std::size_t depth) {
    const Place at = place("nodes", index);
    if (visited[index]) at.fail("is reached twice (the nodes must form a tree)");
    if (depth > kMaxNodeDepth) at.fail("lies deeper than {} nodes", kMaxNodeDepth);
    visited[index] = true;
    const tinygltf::Node& n = m.nodes[index];
    const Transform to_asset = node_transform(n, at).then(parent);
    if (!(std::abs(to_asset.determinant()) > 1e-300)) {  // a scale of 0 (glTF allows it: a hidden node)
      out.notes.push_back({at.path, "a singular transform (a scale of 0) collapses the node and its children: left out"});
      return;
    }
    if (n.mesh >= 0) mesh(checked_index(n.mesh, m.meshes.size(), at / "mesh", "mesh"), to_asset, at);
    if (n.camera >= 0) camera(checked_index(n.camera, m.cameras.size(), at / "camera", "camera"), to_asset);
    if (const Value* l = member(n.extensions, "KHR_lights_punctual")) light(*l, to_asset, at);
    for (std::size_t c = 0; c < n.children.size(); ++c)
      node(checked_index(n.children[c], m.nodes.size(), (at / "children")[c], "node"), to_asset, depth + 1);
  }

  void mesh(std::size_t index, const Transform& to_asset, const Place& node_at) {
    const tinygltf::Mesh& mesh = m.meshes[index];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const Place at = (place("meshes", index) / "primitives")[p];
      const int mode = mesh.primitives[p].mode;
      if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {  // 0 to 3: glTF allows them
        out.notes.push_back({at.path, fmt::format("mode {} (points or lines) has no surface to render: left out", mode)});
        continue;
      }
      if (mode != -1 && mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          mode != TINYGLTF_MODE_TRIANGLE_FAN)
        (at / "mode").fail("{} is not a primitive mode (0 to 6)", mode);
      GltfPrimitive prim = make_primitive(m, mesh.primitives[p], to_asset, at);
      if (prim.material >= 0) checked_index(prim.material, m.materials.size(), at / "material", "material");
      triangles += prim.shape.mesh.triangles.size();
      if (triangles > kMaxMeshTriangles) at.fail("the asset's triangles exceed the limit of {}", kMaxMeshTriangles);
      prim.place = node_at.path + " " + at.path;
      out.primitives.push_back(std::move(prim));
    }
  }

  void camera(std::size_t index, const Transform& to_asset) {
    const tinygltf::Camera& c = m.cameras[index];
    if (c.type != "perspective") return;  // orthographic glTF cameras are not read
    const Place at = place("cameras", index) / "perspective";
    GltfCamera cam;
    cam.position_m = to_asset.translation;
    cam.forward = normalize(to_asset.linear * Vec3{0, 0, -1});
    cam.up = normalize(to_asset.linear * Vec3{0, 1, 0});
    cam.place = at.path;
    cam.yfov_rad = clamp_noted(finite(c.perspective.yfov, at / "yfov"), kMinYfovRad, kMaxYfovRad, "yfov", cam.clamped);
    cam.aspect = finite(c.perspective.aspectRatio, at / "aspectRatio");
    if (cam.aspect != 0.0)  // 0: not given
      cam.aspect = clamp_noted(cam.aspect, kMinAspect, 1.0 / kMinAspect, "aspectRatio", cam.clamped);
    out.cameras.push_back(cam);
  }

  void light(const Value& ext, const Transform& to_asset, const Place& node_at) {
    const Place pe = node_at / "extensions" / "KHR_lights_punctual";
    if (!ext.IsObject() || !ext.Get("light").IsInt()) (pe / "light").fail("expected a light index");
    const std::size_t index = checked_index(ext.Get("light").Get<int>(), m.lights.size(), pe / "light", "light");
    const tinygltf::Light& l = m.lights[index];
    const Place at = (Place{&file, ""} / "extensions" / "KHR_lights_punctual" / "lights")[index];
    GltfLight g;
    g.place = at.path;
    if (l.type == "point") g.type = DeltaLightType::point;
    else if (l.type == "spot") g.type = DeltaLightType::spot;
    else if (l.type == "directional") g.type = DeltaLightType::distant;
    else (at / "type").fail("unknown light type '{}' (point, spot, directional)", l.type);
    g.position_m = to_asset.translation;
    g.direction = normalize(to_asset.linear * Vec3{0, 0, -1});
    g.color = clamp_noted(vec3(l.color, at / "color", {1, 1, 1}), 0.0, kMaxEmissiveStrength, "color", g.clamped);
    const double peak = std::max({g.color.x, g.color.y, g.color.z, 1.0});  // colour × intensity within the limit
    g.intensity = clamp_noted(finite(l.intensity, at / "intensity"), 0.0, kMaxEmissiveStrength / peak, "intensity", g.clamped);
    g.inner_cone_rad = finite(l.spot.innerConeAngle, at / "spot" / "innerConeAngle");
    g.outer_cone_rad = finite(l.spot.outerConeAngle, at / "spot" / "outerConeAngle");
    if (g.type == DeltaLightType::spot) {  // 0 ≤ inner < outer ≤ π/2
      g.outer_cone_rad = clamp_noted(g.outer_cone_rad, kMinConeRad, std::numbers::pi / 2, "spot.outerConeAngle", g.clamped);
      g.inner_cone_rad = clamp_noted(g.inner_cone_rad, 0.0, g.outer_cone_rad, "spot.innerConeAngle", g.clamped);
    }
    out.lights.push_back(g);
  }
};

// ---- into the builder ----------------------------------------------------------------------------

TextureInput texture_input(const GltfTexture& t) {
  return {t.name, t.image, t.transform, t.wrap, t.nearest_magnification};
}

std::string asset_name(const fs::path& file) { return file.filename().string(); }

// The material as the one mapping shared with a scene's "pbr" objects takes it (scene/pbr_material.h):
// its values come clamped into the model (clamp_extensions), its textures with the factors applied.
PbrMaterialInput pbr_input(const GltfMaterial& g) {
  PbrMaterialInput m;
  m.base_color = g.base_color;
  if (const auto& t = g.base_color_texture) m.base_color_texture = texture_input(*t);
  m.metallic = g.metallic;
  m.roughness = g.roughness;
  if (const auto& t = g.metallic_roughness_texture) m.metallic_roughness_texture = texture_input(*t);
  m.emissive = g.emissive;
  m.emissive_strength = g.emissive_strength;
  if (const auto& t = g.emissive_texture) m.emissive_texture = texture_input(*t);
  m.transmission = g.transmission;
  m.thin_walled = g.thickness == 0.0;
  m.ior = g.ior;
  m.dispersion = g.dispersion;
  m.attenuation_color = g.attenuation_color;
  m.attenuation_distance_m = g.attenuation_distance_m;
  return m;
}

std::string clamped_warning(const std::vector<std::string>& notes) {
  return fmt::format("{} (clamped into what Bouguer models, docs/assets.md)", fmt::join(notes, ", "));
}

// What adding an asset's primitives keeps track of: the media made of its volumes, and the
// materials whose clamped values were warned about (once each).
struct AddedSoFar {
  std::set<std::string> media;
  std::set<int> warned;
};

void add_primitive(SceneBuilder& b, const GltfAsset& asset, const GltfPrimitive& p, const GltfObjectInput& in,
                   const Source& where, AddedSoFar& added) {
  ObjectDesc o;
  o.name = fmt::format("{}: {}", in.name.empty() ? asset_name(in.file) : in.name, p.place);
  o.shape = p.shape;
  o.transform = in.transform;
  const Source ws = where / "gltf" / p.place;
  const GltfMaterial fallback;
  const GltfMaterial& g = p.material >= 0 ? asset.materials[std::size_t(p.material)] : fallback;
  const Place at = (Place{&in.file, ""} / "materials")[std::size_t(std::max(p.material, 0))];
  if (const auto& t = g.normal_texture)  // kept under an override: it is the asset's geometry
    o.normal_map = resolve_normal_map({texture_input(*t), g.normal_scale},
                                      at.source() / "normalTexture");
  if (const auto it = in.materials.find(g.name); p.material >= 0 && it != in.materials.end()) {
    const GltfMaterialOverride& ov = it->second;
    const Source wo = where / "materials" / g.name;
    o.inside = ov.inside;
    o.outside = ov.outside;
    o.roughness = ov.roughness;
    o.priority = ov.priority;
    o.material = ov.material;
    o.emission = ov.emission;
    b.object(std::move(o), wo);
    return;
  }
  if (!g.clamped.empty() && added.warned.insert(p.material).second)
    b.warn(at.source(), fmt::format("material '{}': {}", g.name, clamped_warning(g.clamped)));
  PbrRole role = pbr_role(pbr_input(g), at.source());
  o.emission = std::move(role.emission);
  o.material = std::move(role.material);
  if (role.volume) {
    // One medium per material and placement: primitives and instances share it.
    const std::string medium = fmt::format("{}{}: materials[{}] {}", where.path.empty() ? "" : where.path + " ",
                                           asset_name(in.file), p.material, g.name);
    if (added.media.insert(medium).second) b.medium(medium, *role.volume, at.source());
    o.inside = medium;
    o.roughness = role.interface_roughness;
  }
  b.object(std::move(o), ws);
}

// The default scene's extras.bouguer_studio: true or false, or 1 or 0 (Blender 3.4's exporter writes
// a boolean custom property of the scene as 1 or 0).
bool studio_key(const Value& v, const Place& at) {
  if (v.IsBool()) return v.Get<bool>();
  if (v.IsNumber() && (v.GetNumberAsDouble() == 0.0 || v.GetNumberAsDouble() == 1.0)) return v.GetNumberAsDouble() == 1.0;
  at.fail("expected true or false (or 1 or 0)");
}

}  // namespace

bool is_gltf_file(const fs::path& path) { return path.extension() == ".gltf" || path.extension() == ".glb"; }

GltfAsset read_gltf(const fs::path& path) {
  DecodedImages images;
  const Model m = parse_model(path, images);
  GltfAsset out;
  const TextureSources src{m, images, path};
  for (std::size_t i = 0; i < m.materials.size(); ++i)
    out.materials.push_back(material(src, m.materials[i], (Place{&path, ""} / "materials")[i]));
  Walker w{m, path, out, std::vector<bool>(m.nodes.size(), false)};
  std::vector<int> roots;
  if (!m.scenes.empty()) {
    const std::size_t s = m.defaultScene < 0 ? 0 : checked_index(m.defaultScene, m.scenes.size(), Place{&path, "scene"}, "scene");
    roots = m.scenes[s].nodes;
    if (const Value& x = m.scenes[s].extras; x.IsObject() && x.Has("bouguer_studio"))
      out.studio = studio_key(x.Get("bouguer_studio"), Place{&path, "scenes"}[s] / "extras" / "bouguer_studio");
  } else {  // no scenes: every node that is no node's child
    std::vector<bool> child(m.nodes.size(), false);
    for (const auto& n : m.nodes)
      for (int c : n.children)
        if (c >= 0 && std::size_t(c) < child.size()) child[std::size_t(c)] = true;
    for (std::size_t i = 0; i < m.nodes.size(); ++i)
      if (!child[i]) roots.push_back(int(i));
  }
  for (std::size_t r = 0; r < roots.size(); ++r)
    w.node(checked_index(roots[r], m.nodes.size(), (Place{&path, "scenes"} / "nodes")[r], "node"), Transform{}, 0);
  if (out.primitives.empty()) fail("{}: the scene holds no triangles", path.string());
  return out;
}

namespace {

void add_asset_objects(SceneBuilder& b, const GltfAsset& asset, const GltfObjectInput& in, const Source& where) {
  std::vector<std::string> names;
  for (const GltfMaterial& m : asset.materials) names.push_back(m.name);
  for (const auto& [name, ov] : in.materials)
    if (std::find(names.begin(), names.end(), name) == names.end())
      (where / "materials" / name).fail("{} has no material '{}'{}", in.file.filename().string(), name, suggestion(name, names));
  for (const auto& [place, note] : asset.notes) b.warn(Source{in.file, place}, note);
  AddedSoFar added;
  for (const GltfPrimitive& p : asset.primitives) add_primitive(b, asset, p, in, where, added);
}

}  // namespace

void add_gltf_objects(SceneBuilder& b, const GltfObjectInput& in, const Source& where) {
  GltfAsset asset;
  try {
    asset = read_gltf(in.file);
  } catch (const Error& e) {
    (where / "gltf").fail("{}", e.what());
  }
  add_asset_objects(b, asset, in, where);
}

namespace {

bool has_emitters(const GltfAsset& asset) {
  for (const GltfPrimitive& p : asset.primitives)
    if (p.material >= 0 && emits(asset.materials[std::size_t(p.material)])) return true;
  return false;
}

void frame_asset(SceneBuilder& b, const GltfAsset& asset, const Source& where) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const GltfPrimitive& p : asset.primitives)
    for (const Vec3& v : p.shape.mesh.positions) {
      lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
      hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
  const Vec3 centre = (lo + hi) * 0.5;
  const double radius = std::max(0.5 * length(hi - lo), kMinSceneLengthM);
  CameraDesc c;
  c.fov_deg = 40.0;
  const double distance = 1.1 * radius / std::sin(0.5 * c.fov_deg * std::numbers::pi / 180.0);
  c.look_at_m = centre;
  c.position_m = centre + normalize(Vec3{0.0, 0.35, 1.0}) * distance;  // glTF's front is +z, up +y
  b.camera(c, where);
}

}  // namespace

void load_gltf_scene(const fs::path& path, SceneBuilder& b, std::optional<bool> studio) {
  const GltfAsset asset = read_gltf(path);
  const Source top{path, ""};
  if (!asset.cameras.empty()) {
    const GltfCamera& g = asset.cameras.front();
    if (!g.clamped.empty()) b.warn(top / g.place, clamped_warning(g.clamped));
    CameraDesc c;
    c.position_m = g.position_m;
    c.look_at_m = g.position_m + g.forward;
    c.up = g.up;
    const double aspect = g.aspect > 0.0 ? g.aspect : double(c.width_px) / c.height_px;
    // Bouguer's angle spans the shorter side; glTF's yfov the height.
    c.fov_deg = (aspect >= 1.0 ? g.yfov_rad : 2.0 * std::atan(aspect * std::tan(0.5 * g.yfov_rad))) * 180.0 / std::numbers::pi;
    b.camera(c, top / "cameras");
    if (g.aspect > 0.0) b.resolution(std::llround(480.0 * std::max(aspect, 1.0)), std::llround(480.0 / std::min(aspect, 1.0)), top / "cameras");
  } else {
    frame_asset(b, asset, top);
  }
  for (const GltfLight& g : asset.lights) {
    if (!g.clamped.empty()) b.warn(top / g.place, clamped_warning(g.clamped));
    DeltaLightDesc l;
    l.type = g.type;
    l.position_m = g.position_m;
    l.direction = g.direction;
    l.cone_deg = g.outer_cone_rad * 180.0 / std::numbers::pi;
    l.falloff_deg = std::min(g.inner_cone_rad, g.outer_cone_rad) * 180.0 / std::numbers::pi;
    // Candela and lux are Bouguer's luminance units as they are (docs/assets.md).
    l.intensity = resolve_emission(EmissionInput{RgbInput{g.color}, g.intensity}, top / g.place).radiance;
    b.light(l, top / g.place);
  }
  // The default studio: a uniform white (D65) background of luminance 1, where nothing else lights the asset.
  if (studio.value_or(asset.studio.value_or(asset.lights.empty() && !has_emitters(asset))))
    b.background(resolve_emission(EmissionInput{RgbInput{{1, 1, 1}}, 1.0}, top), top);
  b.integrator("path", top);
  b.auto_exposure(true);  // an asset's lights are in candela and lux: expose for them (docs/assets.md)
  add_asset_objects(b, asset, GltfObjectInput{path, Transform{}, {}, {}}, top);
}

}  // namespace bouguer
