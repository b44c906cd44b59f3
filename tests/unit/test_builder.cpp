// The front seam: scenes built in code through the SceneBuilder, as glTF and Python front ends
// will, with the same checks and messages as scene files.
#include <gtest/gtest.h>

#include "bouguer/core/error.h"
#include "bouguer/media/library.h"
#include "bouguer/render/render.h"
#include "bouguer/scene/builder.h"
#include "bouguer/scene/compile.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

// A closed, outward-wound tetrahedron in memory.
TriangleMeshShape tetrahedron(double size_m) {
  TriangleMeshShape t;
  t.mesh.positions = {{0, 0, 0}, {size_m, 0, 0}, {0, size_m, 0}, {0, 0, size_m}};
  t.mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return t;
}

SceneBuilder lit_builder() {
  SceneBuilder b("built-in-code");
  CameraDesc c;
  c.position_m = {0.02, 0.15, 0.25};
  c.look_at_m = {0.01, 0.01, 0.01};
  c.width_px = c.height_px = 12;
  b.camera(c, b.at("camera"));
  RenderSettings s;
  s.integrator = IntegratorType::path;
  s.spp = 16;
  b.settings(s, b.at("render"));
  MediumDesc glass;
  glass.name = "glass";
  glass.ior = ConstantIor{1.5};
  glass.sigma_a_per_m = find_library_material("red-glass")->sigma_a_per_m;
  glass.absorbing = true;
  b.medium(glass, b.at("media.glass"));
  ObjectDesc tet;
  tet.name = "tetrahedron";
  tet.shape = tetrahedron(0.04);
  tet.inside = "glass";
  b.object(tet, b.at("objects[0]"));
  ObjectDesc lamp;
  lamp.name = "lamp";
  lamp.shape = QuadShape{0.5, 0.5};
  lamp.transform = Transform::translate({0, 0, -0.1});
  lamp.emission = EmissionDesc{ConstantSpectrum{1.0}, true, std::nullopt, std::nullopt};
  b.object(lamp, b.at("objects[1]"));
  return b;
}

TEST(SceneBuilder, AnInMemoryMeshRendersAsAGlassObject) {
  const SceneDesc desc = lit_builder().build();
  const RenderScene scene = compile(desc);
  ASSERT_EQ(scene.surfaces.size(), 2u);
  EXPECT_EQ(scene.surfaces[0].kind, SurfaceKind::interface);
  const Film film = test::render_desc(desc);
  // The lamp seen through red glass is red; beside the tetrahedron it is white.
  double red = 0.0, green = 0.0;
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) red += film.rgb_at(x, y).x, green += film.rgb_at(x, y).y;
  EXPECT_GT(red, 1.2 * green);
}

void expect_error(const std::function<void()>& f, const std::string& message) {
  try {
    f();
    FAIL() << "no error; expected " << message;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(SceneBuilder, ChecksEachPartWhereItIsAddedAndNamesThePlace) {
  expect_error(
      [] {
        SceneBuilder b = lit_builder();
        ObjectDesc o;
        o.shape = BoxShape{};
        o.inside = "glas";
        b.object(o, b.at("objects[2]"));
        (void)std::move(b).build();
      },
      "built-in-code: objects[2].inside: unknown medium 'glas' (did you mean 'glass'?)");
  expect_error([] { lit_builder().medium(predefined_media()[1], Source{"built-in-code", "media.air"}); }, "media.air: 'air' is predefined");
  expect_error(
      [] {
        ObjectDesc o;
        o.shape = BoxShape{};
        lit_builder().object(o, Source{"built-in-code", "objects[5]"});
      },
      "objects[5]: give exactly one of 'inside'");
  expect_error(
      [] {
        CameraDesc c;
        c.look_at_m = c.position_m;
        lit_builder().camera(c, Source{"built-in-code", "camera"});
      },
      "camera: 'position' and 'look_at' coincide");
  expect_error(
      [] {
        SceneDesc desc = lit_builder().build();
        auto& mesh = std::get<TriangleMeshShape>(desc.objects[0].shape);
        mesh.mesh.triangles[1][2] = 9;
        (void)compile(desc);
      },
      "object 'tetrahedron': triangle 1 names vertex 9, but there are 4");
}

// Every check is reachable without JSON: plain inputs and a Source, as glTF and Python will give.
TEST(SceneBuilder, ResolvesFrontEndValuesWithoutJson) {
  const Source at{"asset.glb", "materials[3]"};
  EXPECT_DOUBLE_EQ(resolve_length_m(LengthInput{"5 mm"}, at), 0.005);
  expect_error([&] { (void)resolve_positive_length_m(LengthInput{-1.0}, at / "radius"); },
               "asset.glb: materials[3].radius: must be a positive length");
  expect_error([&] { (void)resolve_ior(IorInput{IorLibraryInput{"bk7x"}}, at / "ior"); },
               "asset.glb: materials[3].ior.library: unknown dispersion data 'bk7x'");
  MediumInput wine;
  AbsorptionInput red;
  red.source = AbsorptionLibraryInput{"red-glass"};
  wine.absorption.push_back(red);
  const MediumDesc m = resolve_medium("wine", wine, at);
  EXPECT_TRUE(m.absorbing);
  MediumInput no_ior;
  AbsorptionInput rgb;
  rgb.source = AbsorptionValuesInput{RgbInput{{1, 2, 3}}, "attenuation_per_m", std::nullopt};
  no_ior.absorption.push_back(rgb);
  expect_error([&] { (void)resolve_medium("m", no_ior, at); }, "asset.glb: materials[3]: needs 'ior'");
  expect_error([&] { (void)resolve_surface_material(DiffuseInput{RgbInput{{0.5, 1.5, 0.5}}}, at); },
               "materials[3].reflectance.rgb[1]: a reflectance must lie between 0 and 1");
}

// The command line's overrides pass the same check as a scene's values, once, naming the option.
TEST(SceneBuilder, OverridesPassTheSameCheckNamingTheOption) {
  SceneBuilder b = lit_builder();
  expect_error([&] { b.spp(0, b.at("render.spp")); }, "built-in-code: render.spp: must be between 1 and 1048576 (got 0)");
  try {
    b.spp(0, Source::option("--spp"));
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()), "--spp: must be between 1 and 1048576 (got 0)");
  }
  expect_error([&] { b.resolution(80, 0, Source::option("--resolution")); },
               "--resolution: each side must be 1 to 16384 pixels (got 80x0)");
  expect_error([&] { b.integrator("bidirectional", Source::option("--integrator")); },
               "--integrator: unknown integrator 'bidirectional'");
  b.spp(3, Source::option("--spp")).max_depth(5, Source::option("--max-depth")).resolution(7, 9, Source::option("--resolution"));
  const SceneDesc desc = std::move(b).build();
  EXPECT_EQ(desc.render.spp, 3);
  EXPECT_EQ(desc.render.max_depth, 5);
  EXPECT_EQ(desc.camera.width_px, 7);
  EXPECT_EQ(desc.camera.height_px, 9);
}

}  // namespace
}  // namespace bouguer
