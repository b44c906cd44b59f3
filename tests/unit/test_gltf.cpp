// glTF 2.0 assets (scene/gltf.h): the volume extension against the slab's closed form, the same
// scene from JSON and from glTF, node transforms, material overrides, Draco, and malformed assets.
#include <gtest/gtest.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "bouguer/materials/fresnel.h"
#include "bouguer/spectra/spectral_sampling.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/gltf.h"
#include "bouguer/scene/loader.h"
#include "bouguer/spectra/cie.h"
#include "support/gltf_files.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfDoc;

constexpr double kIor = 1.5;
constexpr double kDistanceM = 0.004;  // attenuationDistance
const Vec3 kColour{0.8, 0.5, 0.25};   // attenuationColor

// A 10 cm square slab of thickness t (the unit cube scaled by its node) with KHR_materials_volume.
GltfDoc volume_slab(double thickness_m, json volume = nullptr) {
  GltfDoc g;
  if (volume.is_null())
    volume = {{"thicknessFactor", thickness_m},
              {"attenuationColor", {kColour.x, kColour.y, kColour.z}},
              {"attenuationDistance", kDistanceM}};
  const int m = g.material({{"name", "Glass"},
                            {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"roughnessFactor", 0.0}}},
                            {"extensions",
                             {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                              {"KHR_materials_volume", volume},
                              {"KHR_materials_ior", {{"ior", kIor}}}}}});
  g.doc["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"};
  g.node({{"name", "slab"}, {"mesh", g.mesh(test::cube_positions(), test::cube_indices(), m)},
          {"scale", {0.1, thickness_m, 0.1}}});
  return g;
}

// The slab lit from below by a D65 panel, seen straight down (test_render.cpp's slab scene).
std::string backlit(const std::string& object, const char* spectral, const std::string& glass = "{}") {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                "width": "20 mm", "resolution": [4, 4]}},
    "render": {{"integrator": "whitted", "spectral": "{}", "spp": 1, "max_depth": 64}},
    "world_medium": "vacuum",
    "media": {{"glass": {{"ior": {}, "absorption": {}}}}},
    "objects": [
      {},
      {{"name": "panel", "shape": {{"type": "quad", "size": [1, 1]}},
        "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}, {{"translate": [0, -0.2, 0]}}],
        "emission": {{"spectrum": "D65", "scale": 1.0}}}}
    ]
  }})",
                     spectral, kIor, glass == "{}" ? R"({"unit": "attenuation_per_m", "rgb": [100, 100, 100]})" : glass,
                     object);
}

// (1−R)²τ/(1−R²τ²) per channel, τ = c^(t/d), for a D65 panel (Y = 1) in the mode's basis.
template <std::size_t N>
Vec3 per_channel_closed_form(const SpectralBasis<N>& basis, double thickness_m) {
  const double r = fresnel_dielectric(1.0, 1.0, kIor);
  const Vec3 white = basis.to_linear_srgb(basis.emission(named_illuminant("D65")));
  const std::array<double, 3> c{kColour.x, kColour.y, kColour.z}, w{white.x, white.y, white.z};
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    const double tau = std::pow(c[i], thickness_m / kDistanceM);
    out[i] = w[i] * (1 - r) * (1 - r) * tau / (1 - r * r * tau * tau);
  }
  return {out[0], out[1], out[2]};
}

fs::path write_slab(const fs::path& dir, double thickness_m, const char* name = "slab.gltf") {
  volume_slab(thickness_m).write(dir / name);
  return dir / name;
}

std::string gltf_object(const fs::path& file) { return fmt::format(R"({{"gltf": "{}"}})", file.string()); }

TEST(Gltf, VolumeSlabMatchesThePerChannelClosedFormInRgb3) {
  const fs::path dir = test::scratch_dir("gltf_rgb3");
  for (const double t : {0.5 * kDistanceM, kDistanceM, 3.0 * kDistanceM}) {
    const fs::path file = write_slab(dir, t, "slab.glb");
    const Film f = test::render_text(backlit(gltf_object(file), "rgb3"));
    const Vec3 expected = per_channel_closed_form(make_rgb3_basis(), t);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(f.rgb_at(1, 2)[c], expected[c], 0.01 * expected[c]) << "t = " << t << " channel " << c;
  }
}

// The lifted σ_a is −ln(c)/d exactly at the rgb3 lines (docs/assets.md).
TEST(Gltf, VolumeAbsorptionIsExactAtTheRgb3Lines) {
  const fs::path dir = test::scratch_dir("gltf_lines");
  const SceneDesc d = parse_scene(backlit(gltf_object(write_slab(dir, kDistanceM)), "rgb3"), dir / "s.json");
  const Spectrum& sigma = d.media.at(*d.objects.at(0).inside).sigma_a_per_m;
  const std::array<double, 3> c{kColour.x, kColour.y, kColour.z};
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_NEAR(eval(sigma, kRgb3WavelengthsNm[i]), -std::log(c[i]) / kDistanceM, 1e-9) << i;
}

TEST(Gltf, VolumeSlabMatchesTheClosedFormInFullAtTheAttenuationDistance) {
  const fs::path dir = test::scratch_dir("gltf_full");
  for (const double t : {0.5 * kDistanceM, kDistanceM, 3.0 * kDistanceM}) {
    const Film f = test::render_text(backlit(gltf_object(write_slab(dir, t)), "full"));
    const Vec3 expected = per_channel_closed_form(make_full_basis(), t);
    for (int c = 0; c < 3; ++c) {
      const double departure = f.rgb_at(1, 2)[c] / expected[c] - 1.0;
      std::printf("full, t = %.1f mm, channel %d: %+.2f %% from the per-channel power law\n", t * 1e3, c, departure * 100);
      if (t == kDistanceM) {
        EXPECT_NEAR(departure, 0.0, 0.01) << "channel " << c;
      }
    }
  }
}

// The σ_a table the reader made of the asset's volume, as a JSON absorption.
std::string absorption_json_of(const fs::path& gltf) {
  const SceneDesc d = parse_scene(backlit(gltf_object(gltf), "full"), gltf.parent_path() / "s.json");
  const auto& t = std::get<TabulatedSpectrum>(d.media.at(*d.objects.at(0).inside).sigma_a_per_m);
  return fmt::format(R"({{"unit": "attenuation_per_m", "wavelength_nm": [{:.17g}], "value": [{:.17g}]}})",
                     fmt::join(t.wavelength_nm, ", "), fmt::join(t.value, ", "));
}

// The cube as an OBJ with the same vertices and triangles, the medium as JSON gives it.
TEST(Gltf, TheSameSceneFromJsonAndFromGltfRendersTheSameImage) {
  const fs::path dir = test::scratch_dir("gltf_same");
  const double t = 0.006;
  const fs::path gltf = write_slab(dir, t);
  std::ofstream obj(dir / "cube.obj");
  for (const Vec3& p : test::cube_positions()) obj << fmt::format("v {} {} {}\n", p.x, p.y, p.z);
  const auto i = test::cube_indices();
  for (std::size_t k = 0; k < i.size(); k += 3) obj << fmt::format("f {} {} {}\n", i[k] + 1, i[k + 1] + 1, i[k + 2] + 1);
  obj.close();
  const std::string json_object = fmt::format(
      R"({{"name": "slab", "shape": {{"type": "mesh", "file": "{}"}}, "transform": [{{"scale": [0.1, {}, 0.1]}}],
          "inside": "glass"}})",
      (dir / "cube.obj").string(), t);
  for (const char* mode : {"rgb3", "full"}) {
    const Film from_json = test::render_text(backlit(json_object, mode, absorption_json_of(gltf)));
    const Film from_gltf = test::render_text(backlit(gltf_object(gltf), mode));
    ASSERT_EQ(from_json.rgb.size(), from_gltf.rgb.size());
    for (std::size_t k = 0; k < from_json.rgb.size(); ++k) ASSERT_EQ(from_json.rgb[k], from_gltf.rgb[k]) << mode << " " << k;
    EXPECT_GT(from_json.rgb_at(1, 2).x, 0.1f);  // the slab is lit: the comparison is not of two black images
  }
}

TEST(Gltf, NodeTransformsPlaceVerticesWhereTheReferenceSays) {
  const fs::path dir = test::scratch_dir("gltf_nodes");
  GltfDoc g;
  const int mesh = g.mesh({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 1, 2});
  const double s = std::sin(std::numbers::pi / 4), c = std::cos(std::numbers::pi / 4);
  // Child: a column-major matrix translating by (0, 0, 5) and scaling x by 3.
  const int child = g.node({{"mesh", mesh}, {"matrix", {3, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}}, false);
  // Parent: translate (1, 2, 3) · rotate 90° about z · scale (2, 2, 2).
  g.node({{"children", {child}}, {"translation", {1, 2, 3}}, {"rotation", {0, 0, s, c}}, {"scale", {2, 2, 2}}});
  g.write(dir / "nodes.gltf");
  const GltfAsset a = read_gltf(dir / "nodes.gltf");
  ASSERT_EQ(a.primitives.size(), 1u);
  // By hand: child (3x, y, z + 5), scale 2, rotate (x, y) → (−y, x), translate.
  auto reference = [](Vec3 p) {
    p = {3 * p.x, p.y, p.z + 5};
    p = p * 2.0;
    p = {-p.y, p.x, p.z};
    return p + Vec3{1, 2, 3};
  };
  const std::vector<Vec3> local{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (std::size_t k = 0; k < 3; ++k) {
    const Vec3 got = a.primitives[0].shape.mesh.positions[k], want = reference(local[k]);
    EXPECT_NEAR(got.x, want.x, 1e-12);
    EXPECT_NEAR(got.y, want.y, 1e-12);
    EXPECT_NEAR(got.z, want.z, 1e-12);
  }
}

// Nested media: an override's priority reaches every primitive of its material.
TEST(Gltf, MaterialOverridesCarryAPriority) {
  const fs::path dir = test::scratch_dir("gltf_priority");
  const fs::path file = write_slab(dir, 0.01);
  const SceneDesc d = parse_scene(
      backlit(fmt::format(R"({{"gltf": "{}", "materials": {{"Glass": {{"inside": "glass", "priority": 3}}}}}})",
                          file.string()),
              "rgb3"),
      dir / "s.json");
  ASSERT_EQ(d.objects.size(), 2u);
  EXPECT_EQ(d.objects[0].priority, 3);
  EXPECT_EQ(compile(d).nested.size(), 1u);
}

TEST(Gltf, MaterialsAreOverriddenByName) {
  const fs::path dir = test::scratch_dir("gltf_override");
  const fs::path file = write_slab(dir, 0.01);
  const std::string scene = backlit(
      fmt::format(R"({{"gltf": "{}", "materials": {{"Glass": {{"inside": "glass"}}}}}})", file.string()), "rgb3");
  const SceneDesc d = parse_scene(scene, dir / "s.json");
  ASSERT_EQ(d.objects.size(), 2u);
  EXPECT_EQ(d.objects[0].inside, "glass");
  // Without the override the asset's own medium is used.
  const SceneDesc own = parse_scene(backlit(gltf_object(file), "rgb3"), dir / "s.json");
  EXPECT_NE(own.objects[0].inside, "glass");
  try {
    parse_scene(backlit(fmt::format(R"({{"gltf": "{}", "materials": {{"Glas": {{"inside": "glass"}}}}}})", file.string()),
                        "rgb3"),
                dir / "s.json");
    FAIL() << "an unknown material name was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("objects[0].materials.Glas: slab.gltf has no material 'Glas' (did you mean 'Glass'?)"),
              std::string::npos)
        << e.what();
  }
}

// Two nodes instancing one mesh share its medium, and one asset placed twice gets two.
TEST(Gltf, InstancesAndPlacementsShareOrSeparateTheirMedia) {
  const fs::path dir = test::scratch_dir("gltf_instances");
  GltfDoc g = volume_slab(0.01);
  g.node({{"mesh", 0}, {"translation", {0, 0.05, 0}}, {"scale", {0.1, 0.01, 0.1}}});
  g.write(dir / "two.glb");
  const std::string one = gltf_object(dir / "two.glb");
  const SceneDesc d = parse_scene(backlit(one + "," + one, "rgb3"), dir / "s.json");
  ASSERT_EQ(d.objects.size(), 5u);
  EXPECT_EQ(d.objects[0].inside, d.objects[1].inside);
  EXPECT_NE(d.objects[0].inside, d.objects[2].inside);
}

TEST(Gltf, DracoMeshesAreDecoded) {
  const fs::path dir = test::scratch_dir("gltf_draco");
  draco::TriangleSoupMeshBuilder mb;
  mb.Start(12);
  const int pos = mb.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const auto p = test::cube_positions();
  const auto i = test::cube_indices();
  for (int f = 0; f < 12; ++f) {
    float v[3][3];
    for (int k = 0; k < 3; ++k) {
      const Vec3 q = p[i[std::size_t(3 * f + k)]];
      v[k][0] = float(q.x), v[k][1] = float(q.y), v[k][2] = float(q.z);
    }
    mb.SetAttributeValuesForFace(pos, draco::FaceIndex(std::uint32_t(f)), v[0], v[1], v[2]);
  }
  std::unique_ptr<draco::Mesh> mesh = mb.Finalize();
  draco::Encoder enc;
  enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  draco::EncoderBuffer buf;
  ASSERT_TRUE(enc.EncodeMeshToBuffer(*mesh, &buf).ok());
  GltfDoc g;
  const int view = g.view(buf.data(), buf.size());
  const int unique_id = int(mesh->attribute(pos)->unique_id());
  g.doc["accessors"].push_back({{"componentType", 5126}, {"count", mesh->num_points()}, {"type", "VEC3"},
                                {"min", {-0.5, -0.5, -0.5}}, {"max", {0.5, 0.5, 0.5}}});
  g.doc["accessors"].push_back({{"componentType", 5125}, {"count", 36}, {"type", "SCALAR"}});
  g.doc["meshes"].push_back(
      {{"primitives",
        {{{"attributes", {{"POSITION", 0}}},
          // As conforming encoders write it: an indices accessor without a bufferView (the faces are
          // in the Draco stream), which tinygltf 2.7 alone refuses (docs/assets.md).
          {"indices", 1},
          {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", {{"POSITION", unique_id}}}}}}}}}}});
  g.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  g.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  g.node({{"mesh", 0}});
  g.write(dir / "draco.glb");
  const GltfAsset a = read_gltf(dir / "draco.glb");
  ASSERT_EQ(a.primitives.size(), 1u);
  const Mesh& m = a.primitives[0].shape.mesh;
  EXPECT_EQ(m.triangles.size(), 12u);
  for (const Vec3& q : m.positions)
    for (double x : {q.x, q.y, q.z}) EXPECT_NEAR(std::abs(x), 0.5, 1e-3);  // 14-bit quantisation
  EXPECT_NEAR(signed_volume(welded(m, 1e-4)), 1.0, 1e-3);
}

// ---- malformed assets: one line naming the file and the problem, exit 1 ----------------------------

struct Bad {
  const char* name;
  std::function<void(GltfDoc&)> edit;
  const char* expected;  // in the message
};

TEST(Gltf, MalformedAssetsGiveOneLineNamingTheFileAndThePlace) {
  const fs::path dir = test::scratch_dir("gltf_bad");
  const std::vector<Bad> cases = {
      {"count", [](GltfDoc& g) { g.doc["accessors"][0]["count"] = 9; }, "accessors[0].count: 9 exceeds bufferView 0"},
      {"stride", [](GltfDoc& g) { g.doc["bufferViews"][0]["byteStride"] = 8; }, "bufferViews[0].byteStride: 8 is less than"},
      {"index", [](GltfDoc& g) {
         std::uint32_t* i = reinterpret_cast<std::uint32_t*>(g.bin.data() + g.doc["bufferViews"][1]["byteOffset"].get<std::size_t>());
         i[5] = 8;
       }, "indices: index 8 at 5 is out of range (the primitive has 8 vertices)"},
      {"matrix", [](GltfDoc& g) {
         g.doc["nodes"][0].erase("scale");
         g.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
         g.doc["nodes"][0]["matrix"][5] = std::numeric_limits<double>::quiet_NaN();  // dumped as null
       }, "nodes[0]"},
      {"zero_distance", [](GltfDoc& g) {
         g.doc["materials"][0]["extensions"]["KHR_materials_volume"]["attenuationDistance"] = 0.0;
       }, "materials[0].extensions.KHR_materials_volume.attenuationDistance: must be positive"},
      {"black", [](GltfDoc& g) {
         g.doc["materials"][0]["extensions"]["KHR_materials_volume"]["attenuationColor"][1] = 0.0;
       }, "KHR_materials_volume.attenuationColor[1]: must lie in (0, 1]"},
      {"huge", [](GltfDoc& g) { g.doc["accessors"][0]["count"] = 4000000000u; }, "accessors[0].count: 4000000000 exceeds"},
      {"view", [](GltfDoc& g) { g.doc["bufferViews"][0]["byteLength"] = 1u << 30; }, "bufferViews[0]"},
      {"cycle", [](GltfDoc& g) { g.doc["nodes"][0]["children"] = {0}; }, "nodes[0]: is reached twice"},
  };
  for (const Bad& b : cases) {
    GltfDoc g = volume_slab(0.01);
    b.edit(g);
    const fs::path file = dir / (std::string(b.name) + ".glb");
    g.write(file);
    const auto r = test::run_bouguer({"render", file.string(), "-o", (dir / "out.png").string(), "--quiet"});
    EXPECT_EQ(r.exit_code, 1) << b.name << ": " << r.err;
    EXPECT_EQ(test::line_count(r.err), 1) << b.name << ": " << r.err;
    EXPECT_NE(r.err.find(file.string()), std::string::npos) << b.name << ": " << r.err;
    EXPECT_NE(r.err.find(b.expected), std::string::npos) << b.name << ": " << r.err;
  }
  // A truncated .glb, and a .gltf whose .bin is missing.
  volume_slab(0.01).write(dir / "whole.glb");
  const std::string whole = test::read_file(dir / "whole.glb");
  for (const std::size_t keep : {std::size_t(10), std::size_t(30), whole.size() / 2, whole.size() - 4}) {
    test::write_file(dir / "truncated.glb", whole.substr(0, keep));
    const auto r = test::run_bouguer({"render", (dir / "truncated.glb").string(), "-o", (dir / "out.png").string()});
    EXPECT_EQ(r.exit_code, 1) << keep << ": " << r.err;
    EXPECT_EQ(test::line_count(r.err), 1) << keep << ": " << r.err;
    EXPECT_NE(r.err.find("truncated.glb"), std::string::npos) << r.err;
  }
  volume_slab(0.01).write(dir / "lonely.gltf");
  fs::remove(dir / "lonely.bin");
  const auto r = test::run_bouguer({"render", (dir / "lonely.gltf").string(), "-o", (dir / "out.png").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("lonely.gltf"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("lonely.bin"), std::string::npos) << r.err;
}

TEST(Gltf, AnAssetRendersDirectlyWithItsCameraAndLights) {
  const fs::path dir = test::scratch_dir("gltf_direct");
  GltfDoc g = volume_slab(0.01);
  g.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"aspectRatio", 1.5}, {"znear", 0.01}}}}};
  g.node({{"camera", 0}, {"translation", {0, 0.05, 0.5}}});
  g.doc["extensionsUsed"].push_back("KHR_lights_punctual");
  g.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 20.0}}}}}}};
  g.node({{"translation", {0, 0.3, 0.3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  g.write(dir / "lit.glb");
  const SceneDesc d = load_scene(dir / "lit.glb");
  EXPECT_EQ(d.camera.width_px, 720);  // 480 high at its aspect ratio
  EXPECT_EQ(d.camera.height_px, 480);
  EXPECT_NEAR(d.camera.position_m.z, 0.5, 1e-12);
  ASSERT_EQ(d.lights.size(), 1u);
  EXPECT_NEAR(d.lights[0].position_m.y, 0.3, 1e-12);
  const auto r = test::run_bouguer({"render", (dir / "lit.glb").string(), "-o", (dir / "lit.png").string(),
                                    "--resolution", "12x8", "--spp", "1", "--quiet"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "lit.png"));
  // Without camera or lights: a framing camera and the default studio background.
  volume_slab(0.01).write(dir / "bare.glb");
  const SceneDesc bare = load_scene(dir / "bare.glb");
  EXPECT_TRUE(bare.lights.empty());
  EXPECT_GT(bare.camera.position_m.z, 0.05);
}

}  // namespace
}  // namespace bouguer
