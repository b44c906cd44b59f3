// The texture channels beyond diffuse reflectance: the JSON texture transform (its v-up
// convention in closed form), glTF metallic-roughness as a mixture BSDF, textured emitters, and
// normal maps.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <random>

#include "bouguer/core/error.h"
#include "bouguer/integrators/events.h"
#include "bouguer/materials/surface_bsdf.h"
#include "bouguer/io/image_io.h"
#include "bouguer/io/texture_image.h"
#include "bouguer/spectra/color_space.h"
#include "bouguer/scene/loader.h"
#include "bouguer/scene/normal_map.h"
#include "bouguer/scene/texture.h"
#include "support/gltf_files.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

namespace fs = std::filesystem;

// A w × h data texture whose texel (x, y) (y from the bottom) is (x, y, 0.5).
TextureImage index_image(int w, int h) {
  TextureImage image;
  image.width = w;
  image.height = h;
  image.srgb = false;
  image.rgb.resize(static_cast<std::size_t>(w * h * 3));
  for (int y = 0; y < h; ++y)  // the file's rows run from the top
    for (int x = 0; x < w; ++x) {
      float* p = &image.rgb[static_cast<std::size_t>(((h - 1 - y) * w + x) * 3)];
      p[0] = static_cast<float>(x);
      p[1] = static_cast<float>(y);
      p[2] = 0.5f;
    }
  return image;
}

// The JSON transform in closed form: uv' = o + R(θ)(s ⊙ uv), v up, R counter-clockwise. For each
// texel centre uv' of a 4 × 4 texture, the surface point uv = (R(θ)⁻¹(uv' − o)) / s must read that
// texel and nothing else (bilinear weights at a texel centre: 1 on it).
TEST(TextureTransform, JsonConventionLandsWhereTheClosedFormSays) {
  const std::array<double, 2> offset{0.3, -0.15}, scale{2.0, 0.5};
  for (const double theta : {0.0, std::numbers::pi / 6.0, std::numbers::pi / 2.0, -2.0}) {
    TextureTable table;
    const int id = add_texture(table, index_image(4, 4), TextureUse::data, uv_transform_v_up(offset, theta, scale));
    for (int ty = 0; ty < 4; ++ty)
      for (int tx = 0; tx < 4; ++tx) {
        // A texel centre, one period away (repeat) so the inverse map is not trivially near 0.
        const double up = (tx + 0.5) / 4.0 + 1.0 - offset[0], vp = (ty + 0.5) / 4.0 - 2.0 - offset[1];
        const double c = std::cos(theta), s = std::sin(theta);
        const std::array<double, 2> uv{(c * up + s * vp) / scale[0], (-s * up + c * vp) / scale[1]};
        const Vec3 rgb = texture_rgb(table, texel_blend(table, id, uv, 0.0));
        EXPECT_NEAR(rgb.x, tx, 1e-5) << "θ " << theta << " texel " << tx << "," << ty;
        EXPECT_NEAR(rgb.y, ty, 1e-5) << "θ " << theta << " texel " << tx << "," << ty;
      }
  }
}

// A quarter turn moves the texture's u axis onto v: with θ = 90°, surface u → lookup v.
TEST(TextureTransform, AQuarterTurnInTheJsonConvention) {
  TextureTable table;
  const int id = add_texture(table, index_image(4, 4), TextureUse::data, uv_transform_v_up({0, 0}, std::numbers::pi / 2, {1, 1}));
  // uv' = R(90°)·uv = (−v, u): the surface point (0.625, 0.125) reads uv' = (−0.125, 0.625) = texel (3, 2).
  const Vec3 rgb = texture_rgb(table, texel_blend(table, id, {0.625, 0.125}, 0.0));
  EXPECT_NEAR(rgb.x, 3.0, 1e-5);
  EXPECT_NEAR(rgb.y, 2.0, 1e-5);
}

std::string textured_quad_json(const fs::path& texture, const std::string& transform) {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1, "resolution": [8, 8]}},
    "objects": [{{"name": "label", "shape": {{"type": "quad", "size": [1, 1]}},
                  "material": {{"type": "diffuse", "reflectance": {{"texture": "{}"{}}}}}}}],
    "lights": [{{"type": "distant", "direction": [0, 0, -1], "spectrum": "D65"}}]
  }})",
                     texture.generic_string(), transform);
}

fs::path write_texture_png(const fs::path& dir) {
  const fs::path png = dir / "t.png";
  // A 2 × 2 PNG through the project's writer.
  Film film(2, 2);
  film.set_rgb(0, 0, {0.2f, 0.4f, 0.6f});
  film.set_rgb(1, 0, {0.6f, 0.4f, 0.2f});
  film.set_rgb(0, 1, {0.1f, 0.1f, 0.1f});
  film.set_rgb(1, 1, {0.9f, 0.9f, 0.9f});
  write_image(png, film);
  return png;
}

// The scene is refused with one line naming the quad's reflectance and holding `expect`.
void expect_reflectance_error(const std::string& scene, const fs::path& dir, const std::string& expect) {
  try {
    parse_scene(scene, dir / "s.json");
    ADD_FAILURE() << expect << ": the scene was accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(expect), std::string::npos) << m;
    EXPECT_NE(m.find("s.json: objects[0].material.reflectance"), std::string::npos) << m;
    EXPECT_EQ(test::line_count(m), 1) << m;
  }
}

TEST(TextureTransform, JsonReadsOffsetRotationAndScale) {
  const fs::path dir = test::scratch_dir("TextureTransformJson");
  const fs::path png = write_texture_png(dir);
  const SceneDesc d = parse_scene(
      textured_quad_json(png, R"(, "transform": {"offset": [0.25, 0.5], "rotation": "30 deg", "scale": [2, 3]})"),
      dir / "s.json");
  const auto& diffuse = std::get<DiffuseDesc>(*d.objects.at(0).material);
  ASSERT_TRUE(diffuse.reflectance_texture);
  const UvTransform want = uv_transform_v_up({0.25, 0.5}, std::numbers::pi / 6.0, {2.0, 3.0});
  const UvTransform& got = diffuse.reflectance_texture->transform;
  EXPECT_NEAR(got.rotation_rad, want.rotation_rad, 1e-15);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(got.offset[i], want.offset[i]);
    EXPECT_EQ(got.scale[i], want.scale[i]);
  }
  // "0.5 rad" is the same unit system; no unit, an unknown unit and a zero scale are one line each.
  EXPECT_NEAR(std::get<DiffuseDesc>(*parse_scene(textured_quad_json(png, R"(, "transform": {"rotation": "0.5 rad"})"),
                                                 dir / "s.json").objects.at(0).material)
                  .reflectance_texture->transform.rotation_rad,
              0.5, 1e-15);
  for (const auto& [transform, expect] :
       {std::pair<std::string, std::string>{R"(, "transform": {"rotation": "30"})", "transform.rotation: '30' has no unit"},
        {R"(, "transform": {"rotation": "30 grad"})", "unknown angle unit 'grad'"},
        {R"(, "transform": {"rotation": 30})", "transform.rotation: expected a string"},
        {R"(, "transform": {"scale": [1, 0]})", "transform.scale[1]: must not be 0"},
        {R"(, "transform": {"shift": [1, 0]})", "transform.shift: unknown key"}}) {
    expect_reflectance_error(textured_quad_json(png, transform), dir, expect);
  }
}

// "wrap": one name for both axes or a pair [along u, along v], checked by the builder: an unknown
// name is one line naming the key (and the name it was likely meant to be), a wrong shape the
// loader's line; a normal map and an emitter's texture take it too.
TEST(TextureWrap, JsonReadsWrapModesAndRefusesUnknownOnes) {
  const fs::path dir = test::scratch_dir("TextureWrapJson");
  const fs::path png = write_texture_png(dir);
  auto sampler = [&](const std::string& wrap) {
    const SceneDesc d = parse_scene(textured_quad_json(png, wrap), dir / "s.json");
    return std::get<DiffuseDesc>(*d.objects.at(0).material).reflectance_texture->sampler;
  };
  using W = std::array<TextureWrap, 2>;
  EXPECT_EQ(sampler("").wrap, (W{TextureWrap::repeat, TextureWrap::repeat}));
  EXPECT_EQ(sampler(R"(, "wrap": "clamp")").wrap, (W{TextureWrap::clamp, TextureWrap::clamp}));
  EXPECT_EQ(sampler(R"(, "wrap": ["mirror", "repeat"])").wrap, (W{TextureWrap::mirror, TextureWrap::repeat}));
  EXPECT_FALSE(sampler(R"(, "wrap": "mirror")").nearest_magnification);
  for (const auto& [wrap, expect] :
       {std::pair<std::string, std::string>{R"(, "wrap": "clam")",
                                            "reflectance.wrap: unknown wrap 'clam' (did you mean 'clamp'?)"},
        {R"(, "wrap": ["repeat", "tile"])", "reflectance.wrap[1]: unknown wrap 'tile' (known: repeat, clamp, mirror)"},
        {R"(, "wrap": ["clamp"])", "reflectance.wrap: expected a wrap name or two"},
        {R"(, "wrap": 33071)", "reflectance.wrap: expected a wrap name or two"}}) {
    expect_reflectance_error(textured_quad_json(png, wrap), dir, expect);
  }
  const SceneDesc n = parse_scene(fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1, "resolution": [8, 8]}},
    "objects": [{{"name": "tile", "shape": {{"type": "quad", "size": [1, 1]}},
                  "material": {{"type": "diffuse", "normal_map": {{"texture": "{0}", "wrap": ["clamp", "mirror"]}}}}}},
                {{"name": "lamp", "shape": {{"type": "quad", "size": [1, 1]}}, "transform": [{{"translate": [0, 0, -1]}}],
                  "emission": {{"spectrum": {{"texture": "{0}", "wrap": "mirror"}}}}}}]
  }})", png.generic_string()), dir / "s.json");
  EXPECT_EQ(n.objects.at(0).normal_map->texture.sampler.wrap, (W{TextureWrap::clamp, TextureWrap::mirror}));
  EXPECT_EQ(n.objects.at(1).emission->texture->sampler.wrap, (W{TextureWrap::mirror, TextureWrap::mirror}));
}


// ---- glTF metallic-roughness --------------------------------------------------------------------

constexpr std::size_t N3 = 3;

MetallicRoughness<N3> mixture(double base, double metalness, double alpha) {
  return {SampledSpectrum<N3>::constant(static_cast<float>(base)), metalness, alpha};
}

Vec3 random_direction(std::mt19937_64& rng, bool upper) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = upper ? u(rng) : 2.0 * u(rng) - 1.0, r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * std::numbers::pi * u(rng);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Closed forms: a white metal (metalness 1, F0 = 1) has Schlick's F = 1, so it is the bare GGX lobe;
// at normal incidence and reflection (h = n, Λ = 0, D = 1/(πα²)) the mix is
// m·F0/(4πα²) + (1 − m)·(0.04/(4πα²) + 0.96·ρ/π); both modes give the same, reciprocal values.
TEST(TextureChannels, MetallicRoughnessClosedForms) {
  std::mt19937_64 rng(3);
  const Bsdf<N3> white_metal = mixture(1.0, 1.0, 0.3);
  for (int i = 0; i < 200; ++i) {
    const Vec3 wo = random_direction(rng, true), wi = random_direction(rng, true);
    EXPECT_NEAR(eval(white_metal, wo, wi, TransportMode::radiance)[1], ConductorBsdf{{0.3}}.eval(wo, wi),
                1e-6 * std::max(1.0, ConductorBsdf{{0.3}}.eval(wo, wi)));
  }
  const Vec3 z{0, 0, 1};
  for (const auto& [m, rho, alpha] : {std::tuple{0.3, 0.6, 0.5}, {0.0, 0.25, 0.8}, {1.0, 0.9, 0.2}}) {
    const double want = m * rho / (4 * std::numbers::pi * alpha * alpha) +
                        (1 - m) * (0.04 / (4 * std::numbers::pi * alpha * alpha) + 0.96 * rho / std::numbers::pi);
    EXPECT_NEAR(eval(Bsdf<N3>{mixture(rho, m, alpha)}, z, z, TransportMode::radiance)[0], want, 1e-6 * want);
  }
  const Bsdf<N3> b = mixture(0.7, 0.4, 0.35);
  for (int i = 0; i < 500; ++i) {
    const Vec3 wo = random_direction(rng, false), wi = random_direction(rng, false);
    const double f = eval(b, wo, wi, TransportMode::radiance)[2], adj = eval(b, wi, wo, TransportMode::importance)[2];
    EXPECT_NEAR(f / std::abs(wi.z), adj / std::abs(wo.z), 1e-5 * std::max(1.0, f / std::abs(wi.z)));
    if (wo.z <= 0.0 || wi.z <= 0.0) {
      EXPECT_EQ(f, 0.0);  // one-sided: the event's frame faces wo
    }
  }
  EXPECT_FALSE(is_specular(b));
}

// Sampling agrees with pdf and eval: every sample's pdf and weight are pdf(wi) and eval/pdf; over
// 32 regions of the hemisphere the share of 200 000 samples matches ∫pdf (by a 256 × 256 midpoint
// quadrature) within 5 standard deviations, and the share of failed samples (a GGX reflection
// below the horizon) matches 1 − ∫pdf over the hemisphere; and the mean weight, an estimate of the
// albedo ∫eval dω whose standard error follows from the weights' spread, matches the quadrature
// within 5 of those errors (it would not if samples came from another density than pdf).
TEST(TextureChannels, MetallicRoughnessSamplingMatchesPdfAndEval) {
  constexpr int kRegionsTheta = 8, kRegionsPhi = 4, kSamples = 200000, kQuad = 256;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const auto& [m, rho, alpha, cos_o] :
       {std::tuple{0.0, 0.8, 0.6, 0.9}, {1.0, 0.5, 0.15, 0.5}, {0.5, 0.3, 0.3, 0.2}, {0.2, 0.9, 0.05, 0.7}}) {
    const Bsdf<N3> b = mixture(rho, m, alpha);
    const Vec3 wo{std::sqrt(1 - cos_o * cos_o), 0.0, cos_o};
    auto region = [&](const Vec3& wi) {
      const int t = std::min(kRegionsTheta - 1, static_cast<int>(wi.z * kRegionsTheta));
      double phi = std::atan2(wi.y, wi.x) + std::numbers::pi;
      const int p = std::min(kRegionsPhi - 1, static_cast<int>(phi / (2 * std::numbers::pi) * kRegionsPhi));
      return t * kRegionsPhi + p;
    };
    // Quadrature over (cos θ, φ), dω = dcos θ dφ.
    std::vector<double> expected(kRegionsTheta * kRegionsPhi, 0.0);
    double pdf_total = 0.0, albedo = 0.0;
    for (int i = 0; i < kQuad; ++i)
      for (int j = 0; j < kQuad; ++j) {
        const double zc = (i + 0.5) / kQuad, phi = 2 * std::numbers::pi * (j + 0.5) / kQuad - std::numbers::pi;
        const double r = std::sqrt(1 - zc * zc);
        const Vec3 wi{r * std::cos(phi), r * std::sin(phi), zc};
        const double d_omega = 2 * std::numbers::pi / (kQuad * kQuad);
        const double p = pdf(b, wo, wi) * d_omega;
        expected[static_cast<std::size_t>(region(wi))] += p;
        pdf_total += p;
        albedo += eval(b, wo, wi, TransportMode::radiance)[0] * d_omega;
      }
    expected.push_back(1.0 - pdf_total);  // the last region: no sample
    std::vector<double> observed(expected.size(), 0.0);
    double sum = 0.0, sum2 = 0.0;
    for (int k = 0; k < kSamples; ++k) {
      const auto s = sample(b, wo, u(rng), u(rng), u(rng), TransportMode::radiance);
      if (!s) {
        observed.back() += 1.0;
        continue;
      }
      ASSERT_NEAR(s->pdf, pdf(b, wo, s->wi), 1e-9 * std::max(1.0, s->pdf));
      ASSERT_NEAR(s->weight[0], eval(b, wo, s->wi, TransportMode::radiance)[0] / s->pdf, 1e-5);
      observed[static_cast<std::size_t>(region(s->wi))] += 1.0;
      sum += s->weight[0];
      sum2 += double(s->weight[0]) * s->weight[0];
    }
    for (std::size_t r = 0; r < expected.size(); ++r) {
      const double e = expected[r] * kSamples, sigma = std::sqrt(std::max(e, 1.0));
      EXPECT_NEAR(observed[r], e, 5 * sigma + 0.002 * kSamples) << "m " << m << " alpha " << alpha << " region " << r;
    }
    const double mean = sum / kSamples, error = std::sqrt((sum2 / kSamples - mean * mean) / kSamples);
    std::printf("metallic-roughness m %.1f ρ %.1f α %.2f cos θo %.1f: albedo %.4f by quadrature, %.4f ± %.4f sampled\n",
                m, rho, alpha, cos_o, albedo, mean, error);
    EXPECT_NEAR(mean, albedo, 5 * error + (alpha < 0.1 ? 0.01 : 0.002));
  }
}

// An 8 × 1 PNG, its left half one colour and its right half another, so a bilinear lookup within
// the middle of each half (u in [3/16, 5/16] or [11/16, 13/16]) reads that colour alone. Values of 0
// and 1 survive the writer's sRGB encoding exactly.
void write_two_texels(const fs::path& path, Vec3f left, Vec3f right) {
  Film image(8, 1);
  for (int x = 0; x < 8; ++x) image.set_rgb(x, 0, x < 4 ? left : right);
  write_image(path, image);
}

// A glTF quad 1 m wide in the xy-plane facing +z, UVs over the whole quad (the image's left edge at
// x = −0.5), one material, its textures from image files beside the asset.
void write_gltf_quad(const fs::path& path, const nlohmann::json& material, const std::vector<std::string>& images) {
  test::GltfDoc g;
  const int m = g.material(material);
  const int mesh = g.mesh({{-0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, -0.5, 0}, {-0.5, -0.5, 0}}, {0, 3, 2, 0, 2, 1}, m);
  const std::vector<float> uv{0, 0, 1, 0, 1, 1, 0, 1};
  g.doc["accessors"].push_back({{"bufferView", g.view(uv.data(), uv.size() * sizeof(float))},
                                {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
  g.doc["meshes"][mesh]["primitives"][0]["attributes"]["TEXCOORD_0"] = g.doc["accessors"].size() - 1;
  g.doc["images"] = nlohmann::json::array();
  g.doc["textures"] = nlohmann::json::array();
  for (std::size_t i = 0; i < images.size(); ++i) {
    g.doc["images"].push_back({{"uri", images[i]}});
    g.doc["textures"].push_back({{"source", i}});
  }
  g.node({{"mesh", mesh}});
  g.write(path);
}

// A scene of `objects` seen head on by an orthographic camera, compiled, with what surface events need.
struct Compiled {
  RenderScene scene;
  Camera camera;
  SpectralTables<N3> tables;
  explicit Compiled(const std::string& objects, const fs::path& dir)
      : scene(compile(parse_scene(fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1, "resolution": [4, 4]}},
      "objects": [{}],
      "lights": [{{"type": "distant", "direction": [0, 0, -1], "spectrum": "D65"}}]
    }})", objects), dir / "s.json"))),
        camera(scene.camera),
        tables(scene.spectra, SpectralMode::rgb3) {}
  // The surface event where a ray down −z through (x, y) meets the scene, seen from +z.
  SurfaceEvent<N3> event_at(double x, double y = 0.0) const {
    const auto hit = scene.rays.intersect(Ray{{x, y, 1.0}, {0, 0, -1}});
    if (!hit) throw std::runtime_error("no hit");
    return surface_event(SceneView<N3>{scene, tables, camera, 8}, *hit, scene.surfaces[hit->geometry], Vec3{0, 0, 1},
                         scene.world_medium, tables.wavelengths(0.5));
  }
};

// A glTF quad with a metallicRoughnessTexture, its left half (R 1, G 0, B 1) and its right (0, 1, 0),
// factors metallic 0.8 and roughness 0.6: the BSDF in the middle of each half has metalness 0.8·B and
// alpha (0.6·G)² (at least kMinMetallicRoughnessAlpha); R, glTF's occlusion, is not read.
TEST(TextureChannels, GltfMetallicRoughnessTextureReachesTheBsdf) {
  const fs::path dir = test::scratch_dir("TextureChannelsMetallicRoughness");
  write_two_texels(dir / "mr.png", {1.0f, 0.0f, 1.0f}, {0.0f, 1.0f, 0.0f});
  write_gltf_quad(dir / "painted.gltf",
                  {{"name", "Painted"},
                   {"pbrMetallicRoughness",
                    {{"baseColorFactor", {0.5, 0.5, 0.5, 1.0}}, {"metallicFactor", 0.8}, {"roughnessFactor", 0.6},
                     {"metallicRoughnessTexture", {{"index", 0}}}}}},
                  {"mr.png"});
  const Compiled c(fmt::format(R"({{"gltf": "{}"}})", (dir / "painted.gltf").generic_string()), dir);
  for (const auto& [x, metalness, alpha] : {std::tuple{-0.25, 0.8, kMinMetallicRoughnessAlpha}, {0.25, 0.0, 0.36}}) {
    const SurfaceEvent<N3> e = c.event_at(x);
    const auto* b = std::get_if<MetallicRoughness<N3>>(&e.bsdf);
    ASSERT_NE(b, nullptr);
    EXPECT_NEAR(b->metalness, metalness, 1e-6) << "x " << x;
    EXPECT_NEAR(b->alpha, alpha, 1e-6) << "x " << x;
    EXPECT_NEAR(b->base_colour[1], 0.5, 0.01);  // the factor, lifted (the lift of grey is flat)
  }
}

// JSON: a conductor's roughness from a texture, alpha the mean of the texel's channels (as stored).
TEST(TextureChannels, JsonConductorRoughnessTexture) {
  const fs::path dir = test::scratch_dir("TextureChannelsConductor");
  write_two_texels(dir / "alpha.png", {1.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.0f});
  const Compiled c(fmt::format(R"({{"name": "plate", "shape": {{"type": "quad", "size": [1, 1]}},
                    "material": {{"type": "conductor", "n": 0.2, "k": 3, "roughness": {{"texture": "{}"}}}}}})",
                               (dir / "alpha.png").generic_string()),
                   dir);
  for (const auto& [x, alpha] : {std::pair{-0.25, 1.0 / 3.0}, {0.25, 2.0 / 3.0}}) {
    const SurfaceEvent<N3> e = c.event_at(x);
    ASSERT_TRUE(std::holds_alternative<ConductorReflection<N3>>(e.bsdf));
    EXPECT_NEAR(std::get<ConductorReflection<N3>>(e.bsdf).alpha, alpha, 1e-6);
  }
}

// ---- textured emitters --------------------------------------------------------------------------

// The mean luminance over a triangle: a uniform texture gives its own; a 64 × 1 texture white on the
// left (u < ½) and black on the right, over the triangle (0, 0), (1, 0), (0, 1), gives the share of
// the triangle's area left of u = ½, 3/4 (the grid's 64 points and the bilinear blur of a texel at
// each edge move it by about 1/64).
TEST(TextureChannels, MeanLuminanceOverATriangle) {
  TextureTable table;
  TextureImage halves;
  halves.width = 64;
  halves.height = 1;
  halves.srgb = false;
  for (int x = 0; x < 64; ++x) halves.rgb.insert(halves.rgb.end(), 3, x < 32 ? 1.0f : 0.0f);
  const int id = add_texture(table, halves, TextureUse::data);
  EXPECT_NEAR(texture_mean_luminance(table, id, {{{0, 0}, {1, 0}, {0, 1}}}), 0.75, 0.03);
  TextureImage flat = halves;
  for (std::size_t i = 0; i < flat.rgb.size(); ++i) flat.rgb[i] = 0.2f * static_cast<float>(1 + i % 3);
  const int uniform = add_texture(table, flat, TextureUse::data);
  EXPECT_NEAR(texture_mean_luminance(table, uniform, {{{0.1, 0.3}, {0.7, 0.2}, {0.4, 0.9}}}),
              0.2126 * 0.2 + 0.7152 * 0.4 + 0.0722 * 0.6, 1e-6);
}

// A textured emitter: a 0.4 m square at 0.3 m above a grey floor, facing down, its texture red on
// the left and dim blue on the right, D65 at Y = 5 times the texel. The camera looks down (the
// emitter's back, black, hides the middle).
constexpr const char* kGreyFloor =
    R"({"name": "floor", "shape": {"type": "quad", "size": [1.2, 1.2]}, "material": {"type": "diffuse", "reflectance": 0.5}})";

std::string emitter_scene(const fs::path& texture, const std::string& integrator, int spp, int seed,
                          const std::string& floor = kGreyFloor) {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1.2, "resolution": [12, 12]}},
    "render": {{"integrator": "{}", "spp": {}, "seed": {}, "spectral": "rgb3", "max_depth": 2}},
    "background": {{"spectrum": "D65", "scale": 0}},
    "objects": [
      {},
      {{"name": "lamp", "shape": {{"type": "quad", "size": [0.4, 0.4]}},
        "transform": [{{"rotate_deg": [180, [1, 0, 0]]}}, {{"translate": [0, 0, 0.3]}}],
        "emission": {{"spectrum": {{"texture": "{}"}}, "scale": 5}}}}
    ]
  }})", integrator, spp, seed, floor, texture.generic_string());
}

fs::path write_emitter_texture(const fs::path& dir) {
  write_two_texels(dir / "lamp.png", {1.0f, 0.2f, 0.2f}, {0.05f, 0.05f, 0.4f});
  return dir / "lamp.png";
}

// The power used to choose lights is the texture-averaged one: the lamp's triangles sum to
// π·A·Y·mean luminance of its texels (as decoded: the PNG is sRGB), and none is zero.
TEST(TextureChannels, TexturedEmitterPowerIsTheTextureMean) {
  const fs::path dir = test::scratch_dir("TextureChannelsEmitterPower");
  const fs::path png = write_emitter_texture(dir);
  const TextureImage image = read_texture_image(png);
  double mean = 0.0;
  for (int i : {0, 7}) {
    const float* p = &image.rgb[static_cast<std::size_t>(3 * i)];
    mean += 0.5 * (0.2126 * srgb_to_linear(p[0]) + 0.7152 * srgb_to_linear(p[1]) + 0.0722 * srgb_to_linear(p[2]));
  }
  const RenderScene scene = compile(parse_scene(emitter_scene(png, "path", 1, 0), dir / "s.json"));
  double power = 0.0;
  int lamps = 0;
  for (std::size_t i = 0; i < scene.lights.size(); ++i)
    if (const auto* a = std::get_if<AreaLight>(&scene.lights[i])) {
      EXPECT_GE(a->texture, 0);
      EXPECT_GT(scene.light_power[i], 0.0);
      power += scene.light_power[i];
      ++lamps;
    }
  EXPECT_EQ(lamps, 2);
  const double want = std::numbers::pi * 0.16 * 5.0 * mean;
  std::printf("textured lamp: power %.5f, π·A·Y·(mean texel luminance) %.5f\n", power, want);
  EXPECT_NEAR(power, want, 0.02 * want);
}

// Path tracing (next-event estimation reads the texture where it samples the lamp, BSDF hits where
// they land, MIS between them), light tracing (light paths start at texels drawn uniformly by area
// and carry the texel's radiance) and bdpt agree on the floor within noise. Per quadrant of the
// floor, the means of two renders (seeds 1, 2) per estimator differ by less than 5 standard errors
// of the difference, the errors estimated from the two renders' pixel differences.
// Per quadrant of the floor (the lamp's shadow left out), the mean of two renders (seeds 1, 2) and
// the variance of that mean, estimated from the two renders' pixel differences.
struct QuadrantEstimate {
  std::array<Vec3, 4> mean{}, variance{};
};

QuadrantEstimate estimate_quadrants(const std::function<std::string(int seed)>& scene) {
  const Film a = test::render_text(scene(1)), b = test::render_text(scene(2));
  QuadrantEstimate e;
  std::array<int, 4> n{};
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 12; ++x) {
      if (x >= 3 && x < 9 && y >= 3 && y < 9) continue;  // the lamp's shadow and its black back
      const std::size_t q = static_cast<std::size_t>((y < 6 ? 0 : 2) + (x < 6 ? 0 : 1));
      const Vec3f pa = a.rgb_at(x, y), pb = b.rgb_at(x, y);
      const Vec3 va{pa.x, pa.y, pa.z}, vb{pb.x, pb.y, pb.z}, d = va - vb;
      e.mean[q] = e.mean[q] + (va + vb) * 0.5;
      e.variance[q] = e.variance[q] + Vec3{d.x * d.x, d.y * d.y, d.z * d.z} * 0.25;  // var of (a + b)/2 per pixel
      ++n[q];
    }
  for (std::size_t q = 0; q < 4; ++q) {
    e.mean[q] = e.mean[q] / n[q];
    e.variance[q] = e.variance[q] / (double(n[q]) * n[q]);
  }
  return e;
}

// The path tracer against the light tracer and bdpt on a scene(integrator, spp, seed): every quadrant
// and channel within 5 standard errors of the difference. Returns the path tracer's estimate.
QuadrantEstimate expect_estimators_agree(const std::function<std::string(const std::string&, int, int)>& scene) {
  auto run = [&](const std::string& integrator, int spp) {
    return estimate_quadrants([&](int seed) { return scene(integrator, spp, seed); });
  };
  const QuadrantEstimate path = run("path", 256), light = run("light", 256), bdpt = run("bdpt", 128);
  for (const auto& [name, other] : {std::pair{"light", &light}, {"bdpt", &bdpt}})
    for (std::size_t q = 0; q < 4; ++q)
      for (std::size_t c = 0; c < 3; ++c) {
        const double diff = path.mean[q][c] - other->mean[q][c];
        const double sigma = std::sqrt(path.variance[q][c] + other->variance[q][c]);
        std::printf("quadrant %zu channel %zu: path %.4f, %s %.4f (difference %.1f σ)\n", q, c, path.mean[q][c], name,
                    other->mean[q][c], diff / sigma);
        EXPECT_LT(std::abs(diff), 5.0 * sigma + 1e-4) << name << " quadrant " << q << " channel " << c;
      }
  return path;
}

// Path tracing (next-event estimation reads the texture where it samples the lamp, BSDF hits where
// they land, MIS between them), light tracing (light paths start at texels drawn uniformly by area
// and carry the texel's radiance) and bdpt agree on the floor within noise.
TEST(TextureChannels, TexturedEmitterPathLightAndBdptAgree) {
  const fs::path dir = test::scratch_dir("TextureChannelsEmitterEstimators");
  const fs::path png = write_emitter_texture(dir);
  const QuadrantEstimate path = expect_estimators_agree(
      [&](const std::string& integrator, int spp, int seed) { return emitter_scene(png, integrator, spp, seed); });
  // The texture shows: the floor under the red half is redder than under the blue half.
  EXPECT_GT(path.mean[0][0] / path.mean[0][2], 1.5 * path.mean[1][0] / path.mean[1][2]);
}

// The metallic-roughness mixture in every estimator: a glTF floor, metal on its left half
// (metalness 1, roughness 0.6) and dielectric on its right (metalness 0, roughness 0.6 × 0.735),
// base colour 0.7, under the textured lamp: path, light tracer (importance mode) and bdpt agree.
TEST(TextureChannels, MetallicRoughnessFloorPathLightAndBdptAgree) {
  const fs::path dir = test::scratch_dir("TextureChannelsMetalFloor");
  const fs::path png = write_emitter_texture(dir);
  write_two_texels(dir / "mr.png", {0.0f, 1.0f, 1.0f}, {0.0f, 0.5f, 0.0f});
  write_gltf_quad(dir / "floor.gltf",
                  {{"name", "Floor"},
                   {"pbrMetallicRoughness",
                    {{"baseColorFactor", {0.7, 0.7, 0.7, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.6},
                     {"metallicRoughnessTexture", {{"index", 0}}}}}},
                  {"mr.png"});
  const std::string floor = fmt::format(R"({{"gltf": "{}", "transform": [{{"scale": 1.2}}]}})",
                                        (dir / "floor.gltf").generic_string());
  const QuadrantEstimate path = expect_estimators_agree([&](const std::string& integrator, int spp, int seed) {
    return emitter_scene(png, integrator, spp, seed, floor);
  });
  EXPECT_GT(path.mean[0][1], 0.0);
}

// glTF emissiveTexture × emissiveFactor × KHR_materials_emissive_strength: the emitter's texture
// holds factor × texel, and its radiance is D65 at Y = strength times that.
TEST(TextureChannels, GltfEmissiveTextureFactorAndStrength) {
  const fs::path dir = test::scratch_dir("TextureChannelsEmissive");
  write_two_texels(dir / "glow.png", {1.0f, 1.0f, 1.0f}, {1.0f, 0.5f, 0.5f});
  write_gltf_quad(dir / "glow.gltf",
                  {{"name", "Glow"},
                   {"emissiveFactor", {0.8, 0.6, 0.4}},
                   {"emissiveTexture", {{"index", 0}}},
                   {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 8.0}}}}}},
                  {"glow.png"});
  {  // the extension must be declared
    nlohmann::json doc = nlohmann::json::parse(test::read_file(dir / "glow.gltf"));
    doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    test::write_file(dir / "glow.gltf", doc.dump());
  }
  const SceneDesc desc = parse_scene(fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1, "resolution": [32, 16]}},
      "objects": [{{"gltf": "{}"}}]
    }})", (dir / "glow.gltf").generic_string()), dir / "s.json");
  const ObjectDesc& o = desc.objects.at(0);
  ASSERT_TRUE(o.emission && o.emission->texture);
  const TextureImage& t = *o.emission->texture->image;
  ASSERT_EQ(t.width, 8);
  const TextureImage texels = read_texture_image(dir / "glow.png");  // the right half as decoded
  const std::array<double, 6> want{0.8, 0.6, 0.4, 0.8, 0.6 * srgb_to_linear(texels.rgb[22]), 0.4 * srgb_to_linear(texels.rgb[23])};
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(t.rgb[i < 3 ? i : 21 + i - 3], want[i], 1e-6) << i;
  // Head on, each half shows strength × its texel (white (1, 1, 1) at Y = 1 renders as (1, 1, 1);
  // a colour through the reflectance lift times D65 within a few per cent). The quad spans pixels 8
  // to 23; pixels 10 and 21 lie between two texels of one half, beyond the bilinear filter's reach
  // of the halves' boundary and of the wrap: a pixel within half a texel of them averages in the
  // other half (at 4 pixels across, the right one converged 6 % above its texel's value).
  const Film film = test::render_desc(desc, 2);
  for (const auto& [x, offset] : {std::pair{10, 0}, {21, 3}}) {
    const Vec3f p = film.rgb_at(x, 8);
    const std::array<float, 3> rgb{p.x, p.y, p.z};
    for (std::size_t c = 0; c < 3; ++c) {
      const double expected = 8.0 * want[static_cast<std::size_t>(offset) + c];
      EXPECT_NEAR(rgb[c], expected, 0.05 * expected) << "pixel " << x << " channel " << c;
    }
  }
}

// JSON refuses a texture where nothing can carry it (a light, the background), in one line.
TEST(TextureChannels, EmissionTextureOnlyOnEmitters) {
  const fs::path dir = test::scratch_dir("TextureChannelsEmissionBad");
  const fs::path png = write_emitter_texture(dir);
  try {
    parse_scene(fmt::format(R"({{"background": {{"spectrum": {{"texture": "{}"}}}},
                                 "objects": [{{"name": "floor", "shape": {{"type": "quad", "size": [1, 1]}},
                                              "material": {{"type": "diffuse"}}}}]}})",
                            png.generic_string()),
                dir / "s.json");
    ADD_FAILURE() << "a textured background was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("s.json: background.spectrum: only an emitting object takes a texture"),
              std::string::npos)
        << e.what();
  }
  try {
    parse_scene(emitter_scene(dir / "missing.png", "path", 1, 0), dir / "s.json");
    ADD_FAILURE() << "a missing texture was accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("objects[1].emission.spectrum.texture"), std::string::npos) << m;
    EXPECT_NE(m.find("missing.png"), std::string::npos) << m;
    EXPECT_EQ(test::line_count(m), 1) << m;
  }
}

// ---- normal maps ---------------------------------------------------------------------------------

// A texel (r, g, b) is the tangent-space normal (2r − 1, 2g − 1, 2b − 1), glTF's scale on x and y:
// (½ + ½ sin θ, ½, ½ + ½ cos θ) tilts the normal by θ towards +u; with scale s, by atan(s·tan θ).
TEST(TextureChannels, TangentSpaceNormalInClosedForm) {
  const Vec3 flat = tangent_space_normal({0.5, 0.5, 1.0}, 1.0);
  EXPECT_NEAR(flat.z, 1.0, 1e-12);
  for (const double theta : {0.2, 0.5, 1.0})
    for (const double scale : {1.0, 0.5, 2.0}) {
      const Vec3 n = tangent_space_normal({0.5 + 0.5 * std::sin(theta), 0.5, 0.5 + 0.5 * std::cos(theta)}, scale);
      EXPECT_NEAR(std::atan2(n.x, n.z), std::atan(scale * std::tan(theta)), 1e-12) << theta << " " << scale;
      EXPECT_NEAR(n.y, 0.0, 1e-12);
      EXPECT_NEAR(length(n), 1.0, 1e-12);
    }
}

// A PNG of one texel value everywhere (8 × 8), stored exactly as the bytes k/255 (the writer encodes
// sRGB, so each value goes in as its decoded value).
Vec3 write_constant_texel(const fs::path& path, std::array<int, 3> k) {
  Film image(8, 8);
  const Vec3f linear{srgb_to_linear(static_cast<float>(k[0] / 255.0)), srgb_to_linear(static_cast<float>(k[1] / 255.0)),
                     srgb_to_linear(static_cast<float>(k[2] / 255.0))};
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) image.set_rgb(x, y, linear);
  write_image(path, image);
  const TextureImage stored = read_texture_image(path);
  return {stored.rgb[0], stored.rgb[1], stored.rgb[2]};
}

// The shading normal at the middle of a scene's first object, seen from +z.
Vec3 mapped_normal_at(const Compiled& c, double x = 0.1, double y = 0.1) {
  const auto hit = c.scene.rays.intersect(Ray{{x, y, 1.0}, {0, 0, -1}});
  if (!hit) throw std::runtime_error("no hit");
  return normal_mapped(c.scene, c.scene.surfaces[hit->geometry], *hit).shading_normal;
}

// A constant normal map on a quad in the xy-plane (u along +x, v along +y, normal +z) tilts the
// normal to the texel's tangent-space normal in that frame; turned 90° about z, the frame turns
// with it; a texture rotation of 90° (uv' = R·uv: u' grows along −y, v' along +x) turns the frame
// the other way; without a normal map the hit keeps its normal.
TEST(TextureChannels, NormalMapTiltsTheShadingNormalInTheTangentFrame) {
  const fs::path dir = test::scratch_dir("TextureChannelsNormalMap");
  const Vec3 texel = write_constant_texel(dir / "tilt.png", {200, 100, 220});
  const Vec3 t = tangent_space_normal(texel, 1.0);
  auto quad = [&](const std::string& normal_map, const std::string& transform) {
    return Compiled(fmt::format(R"({{"name": "tile", "shape": {{"type": "quad", "size": [1, 1]}}{},
                                    "material": {{"type": "diffuse"{}}}}})",
                                transform, normal_map),
                    dir);
  };
  const std::string map = fmt::format(R"(, "normal_map": "{}")", (dir / "tilt.png").generic_string());
  // Texels and bilinear weights are floats: 1e-6.
  const Vec3 plain = mapped_normal_at(quad(map, ""));
  EXPECT_NEAR(plain.x, t.x, 1e-6);
  EXPECT_NEAR(plain.y, t.y, 1e-6);
  EXPECT_NEAR(plain.z, t.z, 1e-6);
  EXPECT_GT(std::acos(t.z), 0.5);  // the tilt is large: the test would see a missing map
  const Vec3 turned = mapped_normal_at(quad(map, R"(, "transform": [{"rotate_deg": [90, [0, 0, 1]]}])"));
  EXPECT_NEAR(turned.x, -t.y, 1e-6);  // T = +y, B = −x
  EXPECT_NEAR(turned.y, t.x, 1e-6);
  EXPECT_NEAR(turned.z, t.z, 1e-6);
  const Vec3 rotated_uv = mapped_normal_at(quad(
      fmt::format(R"(, "normal_map": {{"texture": "{}", "transform": {{"rotation": "90 deg"}}, "scale": 1}})",
                  (dir / "tilt.png").generic_string()),
      ""));
  EXPECT_NEAR(rotated_uv.x, t.y, 1e-6);  // T = ∂p/∂u' = −y, B = ∂p/∂v' = +x
  EXPECT_NEAR(rotated_uv.y, -t.x, 1e-6);
  EXPECT_NEAR(rotated_uv.z, t.z, 1e-6);
  const Vec3 none = mapped_normal_at(quad("", ""));
  EXPECT_NEAR(none.z, 1.0, 1e-12);
}

// glTF normalTexture with scale 0.5: the tangent-space x and y halved (the frame as for the JSON
// quad: glTF's v runs down the image, so the image's up is +y here too).
TEST(TextureChannels, GltfNormalTextureWithScale) {
  const fs::path dir = test::scratch_dir("TextureChannelsGltfNormal");
  const Vec3 texel = write_constant_texel(dir / "bumps.png", {60, 190, 230});
  write_gltf_quad(dir / "bumpy.gltf",
                  {{"name", "Bumpy"},
                   {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
                   {"normalTexture", {{"index", 0}, {"scale", 0.5}}}},
                  {"bumps.png"});
  const Vec3 want = tangent_space_normal(texel, 0.5);
  const Vec3 n = mapped_normal_at(Compiled(fmt::format(R"({{"gltf": "{}"}})", (dir / "bumpy.gltf").generic_string()), dir));
  EXPECT_NEAR(n.x, want.x, 1e-6);
  EXPECT_NEAR(n.y, want.y, 1e-6);
  EXPECT_NEAR(n.z, want.z, 1e-6);
  EXPECT_LT(want.x, -0.1);  // the texel leans towards −u and +v
  EXPECT_GT(want.y, 0.1);
}

// A glTF quad as write_gltf_quad's (u along +x, the image's up along +y, facing +z) with NORMAL +z,
// a normalTexture (image 0) and, unless empty, TANGENT (x, y, z, w per vertex); its node scaled by
// `scale` (a negative x mirrors it).
void write_tangent_quad(const fs::path& path, const std::vector<float>& tangents, const std::string& image,
                        std::array<double, 3> scale = {1, 1, 1}) {
  test::GltfDoc g;
  const int m = g.material({{"name", "Bumpy"}, {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
                            {"normalTexture", {{"index", 0}}}});
  const int mesh = g.mesh({{-0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, -0.5, 0}, {-0.5, -0.5, 0}}, {0, 3, 2, 0, 2, 1}, m);
  g.attribute(mesh, "TEXCOORD_0", {0, 0, 1, 0, 1, 1, 0, 1}, 2);
  g.attribute(mesh, "NORMAL", {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, 3);
  if (!tangents.empty()) g.attribute(mesh, "TANGENT", tangents, 4);
  g.doc["images"] = {{{"uri", image}}};
  g.doc["textures"] = {{{"source", 0}}};
  g.node({{"mesh", mesh}, {"scale", scale}});
  g.write(path);
}

// The same tangent (x, y, z, w) at each of the quad's 4 vertices.
std::vector<float> four(std::array<float, 4> t) {
  std::vector<float> v(16);
  for (std::size_t i = 0; i < 16; ++i) v[i] = t[i % 4];
  return v;
}

// TANGENT replaces the frame of the UVs (T = +x, B = +y here): a tangent turned 90° to +y with
// w = +1 makes B = N × T = −x, so a texel's tangent-space normal t lands at (−t.y, t.x, t.z); with
// w = −1, B = +x and (t.y, t.x, t.z). Mirrored by its node (scale x −1), the asset's normal is the
// mirror image of the unmirrored one's, (t.y, t.x, t.z) again for w = +1: the node's determinant
// flips w, as the scene's own mirroring transform does. Without TANGENT the UVs' frame gives t itself.
TEST(TextureChannels, GltfTangentAttributeGivesTheFrame) {
  const fs::path dir = test::scratch_dir("TextureChannelsGltfTangent");
  const Vec3 texel = write_constant_texel(dir / "tilt.png", {200, 100, 220});
  const Vec3 t = tangent_space_normal(texel, 1.0);
  EXPECT_GT(std::abs(t.x), 0.2);  // both tangent-space components large: a swapped or missing frame shows
  EXPECT_GT(std::abs(t.y), 0.2);
  struct Case {
    std::vector<float> tangents;
    std::array<double, 3> scale;
    Vec3 want;
  };
  const std::vector<Case> cases = {{{}, {1, 1, 1}, t},
                                   {four({0, 1, 0, 1}), {1, 1, 1}, {-t.y, t.x, t.z}},
                                   {four({0, 1, 0, -1}), {1, 1, 1}, {t.y, t.x, t.z}},
                                   {four({0, 1, 0, 1}), {-1, 1, 1}, {t.y, t.x, t.z}},
                                   {four({0, 2, 0.5, 1}), {1, 1, 1}, {-t.y, t.x, t.z}}};  // Gram–Schmidt, length
  for (std::size_t i = 0; i < cases.size(); ++i) {
    write_tangent_quad(dir / "quad.gltf", cases[i].tangents, "tilt.png", cases[i].scale);
    const Vec3 n = mapped_normal_at(Compiled(fmt::format(R"({{"gltf": "{}"}})", (dir / "quad.gltf").generic_string()), dir));
    EXPECT_NEAR(n.x, cases[i].want.x, 1e-6) << "case " << i;
    EXPECT_NEAR(n.y, cases[i].want.y, 1e-6) << "case " << i;
    EXPECT_NEAR(n.z, cases[i].want.z, 1e-6) << "case " << i;
  }
  // The scene's own transform mirrors as the node does (geometry/transform.cpp flips w too).
  write_tangent_quad(dir / "quad.gltf", four({0, 1, 0, 1}), "tilt.png");
  const Vec3 n = mapped_normal_at(Compiled(
      fmt::format(R"({{"gltf": "{}", "transform": [{{"scale": [-1, 1, 1]}}]}})", (dir / "quad.gltf").generic_string()), dir));
  EXPECT_NEAR(n.x, t.y, 1e-6);
  EXPECT_NEAR(n.y, t.x, 1e-6);
  EXPECT_NEAR(n.z, t.z, 1e-6);
}

// A TANGENT that is not VEC4 float, has a count other than POSITION's, a NaN, a zero vector, or a
// w other than ±1: one line naming the asset and the accessor or attribute, exit 1.
TEST(TextureChannels, MalformedGltfTangentsAreOneLine) {
  const fs::path dir = test::scratch_dir("TextureChannelsBadTangent");
  write_constant_texel(dir / "tilt.png", {200, 100, 220});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  struct Bad {
    const char* name;
    std::vector<float> tangents;
    std::function<void(nlohmann::json&)> edit;  // on the TANGENT accessor
    const char* expected;
  };
  const std::vector<Bad> cases = {
      {"count", four({1, 0, 0, 1}), [](nlohmann::json& a) { a["count"] = 3; },
       "attributes.TANGENT: 3 elements where POSITION has 4"},
      {"vec3", four({1, 0, 0, 1}), [](nlohmann::json& a) { a["type"] = "VEC3"; },
       "where 4 components are needed (meshes[0].primitives[0].attributes.TANGENT)"},
      {"bytes", four({1, 0, 0, 1}), [](nlohmann::json& a) { a["componentType"] = 5121; a["normalized"] = true; },
       "componentType: 5121 is not accepted here (meshes[0].primitives[0].attributes.TANGENT)"},
      {"nan", {1, 0, 0, 1, nan, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}, nullptr,
       "attributes.TANGENT: tangent 1 (nan, 0, 0) is zero or not finite"},
      {"zero", {1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1}, nullptr,
       "attributes.TANGENT: tangent 2 (0, 0, 0) is zero or not finite"},
      {"w", {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 0.5f}, nullptr,
       "attributes.TANGENT: tangent 3: w is 0.5, not the handedness 1 or -1"},
  };
  for (const Bad& b : cases) {
    write_tangent_quad(dir / "bad.gltf", b.tangents, "tilt.png");
    if (b.edit) {
      nlohmann::json doc = nlohmann::json::parse(test::read_file(dir / "bad.gltf"));
      b.edit(doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"].get<std::size_t>()]);
      test::write_file(dir / "bad.gltf", doc.dump());
    }
    const test::RunResult r = test::run_bouguer({"render", (dir / "bad.gltf").string(), "-o", (dir / "out.png").string()});
    SCOPED_TRACE(std::string(b.name) + ": " + r.err);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(test::line_count(r.err), 1);
    EXPECT_NE(r.err.find("bad.gltf"), std::string::npos);
    EXPECT_NE(r.err.find(b.expected), std::string::npos);
  }
}

// A normal map that is missing, or not an image, is one line naming the file and the key.
TEST(TextureChannels, BadNormalMapsAreOneLine) {
  const fs::path dir = test::scratch_dir("TextureChannelsBadNormalMap");
  test::write_file(dir / "notes.png", "not an image\n");
  for (const char* name : {"missing.png", "notes.png"}) {
    try {
      Compiled(fmt::format(R"({{"name": "tile", "shape": {{"type": "quad", "size": [1, 1]}},
                              "material": {{"type": "diffuse", "normal_map": "{}"}}}})",
                           (dir / name).generic_string()),
               dir);
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("objects[0].material.normal_map.texture"), std::string::npos) << m;
      EXPECT_NE(m.find(name), std::string::npos) << m;
      EXPECT_EQ(test::line_count(m), 1) << m;
    }
  }
}

// glTF: a metallicRoughness, emissive or normal texture whose image is missing or not an image is one
// line naming the asset, the image and the file.
TEST(TextureChannels, BadGltfTexturesAreOneLine) {
  const fs::path dir = test::scratch_dir("TextureChannelsBadGltf");
  test::write_file(dir / "notes.png", "not an image\n");
  const std::vector<std::pair<std::string, nlohmann::json>> materials = {
      {"metallicRoughnessTexture", {{"name", "M"}, {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}}}}}}},
      {"emissiveTexture", {{"name", "E"}, {"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 0}}}}},
      {"normalTexture", {{"name", "N"}, {"normalTexture", {{"index", 0}}}}}};
  for (const auto& [key, material] : materials)
    for (const char* image : {"missing.png", "notes.png"}) {
      write_gltf_quad(dir / "bad.gltf", material, {image});
      const test::RunResult r = test::run_bouguer({"render", (dir / "bad.gltf").string(), "-o", (dir / "out.png").string()});
      SCOPED_TRACE(key + " " + image + ": " + r.err);
      EXPECT_EQ(r.exit_code, 1);
      EXPECT_EQ(test::line_count(r.err), 1);
      EXPECT_NE(r.err.find("bad.gltf"), std::string::npos);
      EXPECT_NE(r.err.find("images[0]"), std::string::npos);
      EXPECT_NE(r.err.find(image), std::string::npos);
    }
}

}  // namespace
}  // namespace bouguer
