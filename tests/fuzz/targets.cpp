#include "fuzz/targets.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <fstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "bouguer/geometry/mesh.h"
#include "bouguer/geometry/shapes.h"
#include "bouguer/io/image_io.h"
#include "bouguer/core/limits.h"
#include "bouguer/spectra/spectrum_csv.h"
#include "bouguer/io/texture_image.h"
#include "bouguer/io/vdb.h"
#include "bouguer/media/concentration_field.h"
#include "bouguer/media/majorant.h"
#include "bouguer/scene/texture.h"
#include "bouguer/scene/compile.h"
#include "bouguer/lights/environment.h"
#include "bouguer/scene/gltf.h"
#include "bouguer/scene/loader.h"
#include "bouguer/scene/material_file.h"
#include "bouguer/spectra/cie.h"

namespace bouguer::fuzz {
namespace {
namespace fs = std::filesystem;

fs::path write(const fs::path& dir, const char* name, std::string_view bytes) {
  const fs::path path = dir / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("fuzz: cannot write " + path.string());
  return path;
}

template <typename... Args>
void require(bool ok, fmt::format_string<Args...> format, Args&&... args) {
  if (!ok) throw std::logic_error("fuzz check failed: " + fmt::format(format, std::forward<Args>(args)...));
}

void check_spectrum(const TabulatedSpectrum& s, const char* what) {
  require(!s.value.empty() && s.value.size() == s.wavelength_nm.size(), "{}: table sizes", what);
  for (std::size_t i = 0; i < s.value.size(); ++i) {
    require(std::isfinite(s.value[i]), "{}: value {} is {}", what, i, s.value[i]);
    require(s.wavelength_nm[i] >= kMinWavelengthNm && s.wavelength_nm[i] <= kMaxWavelengthNm, "{}: wavelength {}",
            what, s.wavelength_nm[i]);
    require(i == 0 || s.wavelength_nm[i] > s.wavelength_nm[i - 1], "{}: wavelengths do not increase", what);
  }
}

void check_vec3(const Vec3& v, const char* what) {
  require(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z), "{}: ({}, {}, {})", what, v.x, v.y, v.z);
}

void check_film(const Film& f) {
  require(f.width > 0 && f.height > 0, "film size {} x {}", f.width, f.height);
  require(f.rgb.size() == 3 * static_cast<std::size_t>(f.width) * f.height, "film rgb size");
  for (float v : f.rgb) require(std::isfinite(v), "film rgb value {}", v);
  for (float v : f.spectral) require(std::isfinite(v), "film spectral value {}", v);
}

// What compile() does with a mesh: weld it and ask whether it is closed.
void check_mesh(const fs::path& path) {
  for (const ShapePart& part : make_shape(MeshShape{path}, "fuzz")) {
    const Mesh& m = part.mesh;
    require(!m.triangles.empty(), "mesh accepted without triangles");
    for (const Vec3& p : m.positions) check_vec3(p, "vertex");
    for (const auto& t : m.triangles)
      for (const auto k : t) require(k < m.positions.size(), "index {} of {}", k, m.positions.size());
    const double tolerance = 1e-9 * std::max(max_extent(m), 1e-6);
    (void)closed_surface_problem(welded(m, tolerance));
    require(std::isfinite(signed_volume(m)), "volume {}", signed_volume(m));
  }
}

void spectrum_csv(std::string_view bytes, const fs::path& dir) {
  const fs::path path = write(dir, "input.csv", bytes);
  const TabulatedSpectrum s = load_spectrum_csv(path, {.allow_negative = true});
  check_spectrum(s, "spectrum");
  check_vec3(spectrum_to_xyz(s), "XYZ");
  check_spectrum(load_spectrum_csv(path), "non-negative spectrum");
}

void material_csv(std::string_view bytes, const fs::path& dir) {
  const fs::path path = write(dir, "input.csv", bytes);
  (void)has_unit_header(path);
  const ResolvedMaterial r = resolve_material(path.string(), 1.0);
  require(r.file.has_value(), "material file not kept");
  check_spectrum(r.file->values, "material values");
  require(r.ior >= 1.0 && r.ior < 5.0, "ior {}", r.ior);
  const auto* sigma = std::get_if<TabulatedSpectrum>(&r.sigma_a_per_m);
  require(sigma != nullptr, "sigma_a is not a table");
  check_spectrum(*sigma, "sigma_a");
  for (double v : sigma->value) require(v >= 0.0, "negative sigma_a {}", v);
}

void obj(std::string_view bytes, const fs::path& dir) {
  const std::size_t split = bytes.find(kMtlSeparator);
  write(dir, "input.mtl", split == std::string_view::npos ? "" : bytes.substr(split + kMtlSeparator.size()));
  check_mesh(write(dir, "input.obj", bytes.substr(0, split)));
}

// The same input through the MTL reader (load_obj_materials): each part's mesh and UVs, each
// material's Kd in [0, 1]. A map_Kd names a file beside the input (mostly missing: not read here).
void mtl(std::string_view bytes, const fs::path& dir) {
  const std::size_t split = bytes.find(kMtlSeparator);
  write(dir, "input.mtl", split == std::string_view::npos ? "" : bytes.substr(split + kMtlSeparator.size()));
  const ObjWithMaterials obj = load_obj_materials(write(dir, "input.obj", bytes.substr(0, split)), "fuzz");
  require(!obj.parts.empty(), "no parts");
  for (const ObjMaterial& m : obj.materials)
    for (std::size_t c = 0; c < 3; ++c) require(m.kd[c] >= 0.0 && m.kd[c] <= 1.0, "Kd {}", m.kd[c]);
  for (const ObjPart& part : obj.parts) {
    require(part.material < static_cast<int>(obj.materials.size()), "material {}", part.material);
    require(part.mesh.uvs.empty() || part.mesh.uvs.size() == part.mesh.positions.size(), "uv count");
    for (const auto& uv : part.mesh.uvs) require(std::isfinite(uv[0]) && std::isfinite(uv[1]), "uv");
    for (const auto& t : part.mesh.triangles)
      for (const auto k : t) require(k < part.mesh.positions.size(), "index {} of {}", k, part.mesh.positions.size());
  }
}

void ply(std::string_view bytes, const fs::path& dir) { check_mesh(write(dir, "input.ply", bytes)); }

void exr(std::string_view bytes, const fs::path& dir) { check_film(read_exr(write(dir, "input.exr", bytes))); }

void pfm(std::string_view bytes, const fs::path& dir) { check_film(read_pfm(write(dir, "input.pfm", bytes))); }

// An EXR or a PFM (by its first bytes) as an environment light, sampled as the integrators do.
void environment(std::string_view bytes, const fs::path& dir) {
  const bool is_pfm = bytes.starts_with("P");
  const fs::path path = write(dir, is_pfm ? "input.pfm" : "input.exr", bytes);
  const EnvironmentMap env = load_environment({.file = path, .scale = 2.5, .rotate_deg = 30.0});
  require(env.total_weight >= 0.0 && std::isfinite(env.total_weight), "total weight {}", env.total_weight);
  for (const Vec3f& c : env.rgb) require(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z), "texel");
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const auto s = env.sample((i + 0.5) / 8.0, (j + 0.5) / 8.0);
      if (!s) continue;
      check_vec3(s->wi, "sampled direction");
      require(std::isfinite(s->pdf) && s->pdf > 0.0, "pdf {}", s->pdf);
      require(std::isfinite(env.pdf(s->wi)), "pdf of a sampled direction");
    }
}

// A texture image (PNG, JPEG, EXR, HDR, TIFF by its first bytes: the extension picks OpenImageIO's
// reader), read from a file and from memory, made into a reflectance pyramid and looked up.
void texture(std::string_view bytes, const fs::path& dir) {
  const char* name = bytes.starts_with("\x89PNG")             ? "input.png"
                     : bytes.starts_with("\xff\xd8")           ? "input.jpg"
                     : bytes.starts_with("\x76\x2f\x31\x01") ? "input.exr"
                     : bytes.starts_with("#?")                 ? "input.hdr"
                     : bytes.starts_with("II") || bytes.starts_with("MM") ? "input.tif"
                                                                          : "input.png";
  const TextureImage image = read_texture_image(write(dir, name, bytes));
  const TextureImage same = read_texture_image(
      std::span(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()), name);
  require(same.width == image.width && same.height == image.height, "memory and file disagree on the size");
  require(image.width > 0 && image.height > 0 &&
              image.rgb.size() == 3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height),
          "image size {} x {}, {} values", image.width, image.height, image.rgb.size());
  for (float v : image.rgb) require(std::isfinite(v), "value {}", v);
  if (image.rgb.size() > (std::size_t{3} << 20)) return;  // the pyramid's cost is not what this tests
  TextureTable table;
  const int id = add_texture(table, image, TextureUse::reflectance);
  for (int i = 0; i < 16; ++i) {
    const Vec3 c = texture_rgb(table, texel_blend(table, id, {i * 0.37 - 2.0, i * 0.61 - 3.0}, i * 0.5 - 1.0));
    check_vec3(c, "texel");
    require(c.x >= -1e-6 && c.x <= 1.0 + 1e-6, "reflectance {}", c.x);
  }
}

// A scene file through the loader and the SceneBuilder; small scenes are compiled too (meshes,
// environment maps and CSVs they name are read relative to the input, so mostly refused).
void scene(std::string_view bytes, const fs::path& dir) {
  const fs::path path = write(dir, "input.json", bytes);
  const SceneDesc desc = parse_scene(std::string(bytes), path);
  check_vec3(desc.camera.position_m, "camera position");
  require(desc.camera.width_px >= 1 && desc.camera.height_px >= 1, "resolution {}x{}", desc.camera.width_px,
          desc.camera.height_px);
  std::uint64_t triangles = 0;
  for (const ObjectDesc& o : desc.objects) triangles += triangle_bound(o.shape);
  if (triangles > 20000 || desc.objects.size() > 64) return;  // tessellation is not what this harness tests
  const RenderScene compiled = compile(desc);
  require(compiled.surfaces.size() >= desc.objects.size(), "surfaces {} for {} objects", compiled.surfaces.size(),
          desc.objects.size());
  check_vec3(compiled.bounds.centre_m, "scene centre");
  require(std::isfinite(compiled.bounds.radius_m) && compiled.bounds.radius_m > 0.0, "scene radius {}",
          compiled.bounds.radius_m);
}

// A .glb asset (its JSON and binary chunks; a .gltf's JSON alone when it does not start with the
// GLB magic): what the reader accepts is finite, its indices in range, and the builder takes it.
void gltf(std::string_view bytes, const fs::path& dir) {
  const bool glb = bytes.substr(0, 4) == "glTF";
  const fs::path path = write(dir, glb ? "input.glb" : "input.gltf", bytes);
  const GltfAsset asset = read_gltf(path);
  for (const GltfPrimitive& p : asset.primitives) {
    const Mesh& m = p.shape.mesh;
    for (const Vec3& v : m.positions) check_vec3(v, "vertex");
    for (const auto& t : m.triangles)
      for (const auto k : t) require(k < m.positions.size(), "index {} of {}", k, m.positions.size());
    require(p.shape.normals.empty() || p.shape.normals.size() == m.positions.size(), "normals");
    require(p.material < int(asset.materials.size()), "material {}", p.material);
  }
  for (const GltfCamera& c : asset.cameras) check_vec3(c.position_m, "camera");
  SceneBuilder b(path);
  load_gltf_scene(path, b);
  (void)std::move(b).build();
}

// A .vdb file: its first float grid ("density" when it has one) as a grid field, walked along a
// few rays as the renderer does. Every value it gives is finite, >= 0 and within the maxima, and
// the tracking majorant's pieces bound the column density.
void vdb(std::string_view bytes, const fs::path& dir) {
  const fs::path path = write(dir, "input.vdb", bytes);
  const std::vector<std::string> names = vdb_grid_names(path);
  if (names.empty()) return;
  const bool has_density = std::find(names.begin(), names.end(), "density") != names.end();
  VdbGrid g = read_vdb_grid(path, has_density ? "density" : names.front());
  const auto& n = g.values.nodes;
  require(n[0] >= 2 && n[1] >= 2 && n[2] >= 2, "nodes {}x{}x{}", n[0], n[1], n[2]);
  require(g.values.value.size() == std::size_t(n[0]) * n[1] * n[2], "value count");
  for (float v : g.values.value) require(std::isfinite(v) && v >= 0.0f && v <= g.values.max_value, "value {}", v);
  const double det = Transform{g.world_per_index, {}}.determinant();
  if (!(std::isfinite(det) && std::abs(det) > 1e-30)) return;  // the loader refuses it
  const Mat3 index_per_m = inverse(g.world_per_index);
  const GridField f{std::make_shared<const GridValues>(std::move(g.values)), index_per_m,
                    -(index_per_m * g.node_origin_m), 1.0};
  const Vec3 centre = g.world_per_index * Vec3{n[0] * 0.5, n[1] * 0.5, n[2] * 0.5} + g.node_origin_m;
  const double reach = length(g.world_per_index * Vec3{double(n[0]), double(n[1]), double(n[2])});
  if (!std::isfinite(reach)) return;
  for (const Vec3& d : {Vec3{1, 0, 0}, Vec3{0, -1, 0}, normalize(Vec3{1, 2, 3}), normalize(Vec3{-0.3, 0.1, 1})}) {
    const Vec3 o = centre - d * reach;
    const double column = column_density(f, o, d, 0.0, 2.0 * reach);
    const double peak = max_concentration_on(f, o, d, 0.0, 2.0 * reach);
    require(std::isfinite(column) && column >= 0.0, "column density {}", column);
    require(peak >= 0.0 && peak <= max_concentration(f), "peak {} of {}", peak, max_concentration(f));
    require(column <= peak * 2.0 * reach * (1.0 + 1e-9) + 1e-300, "column {} above peak {} × length", column, peak);
    // The tracking majorant (a piece per cell): in order, inside the segment, bounded, above the column.
    const ConcentrationField field = f;  // the majorant refers to it
    DensityMajorant majorant(field, o, d, 2.0 * reach);
    double end = 0.0, integral = 0.0;
    for (MajorantSegment s; majorant.next(s);) {
      require(s.t0 >= end && s.t1 > s.t0 && s.t1 <= 2.0 * reach, "piece [{}, {}] after {}", s.t0, s.t1, end);
      require(s.density >= 0.0 && s.density <= max_concentration(f), "piece bound {}", s.density);
      integral += s.density * (s.t1 - s.t0);
      end = s.t1;
    }
    require(integral >= column * (1.0 - 1e-9), "majorant integral {} below column {}", integral, column);
  }
}

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"spectrum_csv", spectrum_csv}, {"material_csv", material_csv}, {"obj", obj}, {"ply_ascii", ply},
      {"ply_binary", ply},            {"exr", exr},                   {"pfm", pfm}, {"environment", environment},
      {"scene", scene},           {"vdb", vdb},                   {"gltf", gltf},
      {"texture", texture},         {"mtl", mtl},
  };
  return all;
}

const Target* find_target(std::string_view name) {
  for (const Target& t : targets())
    if (name == t.name) return &t;
  return nullptr;
}

}  // namespace bouguer::fuzz
