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

// The checks that lived in the JSON loader or in compile are the builder's (#35): a front end that
// hands the builder plain values (glTF, Python, Blender) meets each of them, with the same message
// a scene file gets. Each case is a value the loader used to refuse before the builder saw it.
TEST(SceneBuilder, RefusesWhatTheLoaderAndCompileUsedToRefuse) {
  const Source at{"from-blender", "media.dye"};
  auto medium_with = [&](ConcentrationField field) {
    MediumDesc m;
    m.name = "dye";
    m.ior = ConstantIor{1.33};
    m.absorbing = true;
    m.field_absorbers.push_back({ConstantSpectrum{10.0}, std::move(field)});
    lit_builder().medium(m, at);
  };
  expect_error([&] { medium_with(LinearField{{}, -1.0, 2.0}); },
               "from-blender: media.dye.absorption.concentration.value: a concentration must not be negative (got -1)");
  expect_error([&] { medium_with(LayersField{{}, {0.01, 0.005}, {1, 2}}); },
               "media.dye.absorption.concentration.layers[1][0]: layer bounds must increase (0.005 m follows 0.01 m)");
  expect_error([&] { medium_with(LayersField{{}, {0.01}, {-1}}); },
               "media.dye.absorption.concentration.layers[0][1]: a concentration must not be negative");
  expect_error([&] { medium_with(LayersField{{}, {}, {}}); }, "concentration.layers: needs 1 to 256 layers (got 0)");
  expect_error([&] { medium_with(DiffusionField{{}, 1.0, 1e-12}); },
               "media.dye.absorption.concentration.width: the diffusion width 1e-12 m is outside");
  expect_error([&] { medium_with(ExponentialField{{}, 1.0, -0.002}); },
               "concentration.scale_length: must be a positive length");
  expect_error([&] { medium_with(LinearField{{{0, 0, 0}, {0, 0, 0}}, 1.0, 2.0}); },
               "concentration.axis: must be a direction of finite, non-zero length");
  expect_error([&] { medium_with(ConstantField{-0.5}); }, "media.dye.absorption.concentration: must not be negative (got -0.5)");
  expect_error([&] { medium_with(GridField{nullptr, Mat3::identity(), {}, -1.0}); },
               "media.dye.absorption.concentration.scale: must not be negative (got -1)");
  // Eight absorbers and the scatterers' own: nine in the compiled medium.
  expect_error(
      [&] {
        MediumDesc m;
        m.name = "milky";
        m.ior = ConstantIor{1.33};
        m.absorbing = true;
        for (int i = 0; i < 8; ++i) m.field_absorbers.push_back({ConstantSpectrum{1.0}, ConstantField{1.0}});
        m.scattering = ScatteringDesc{ConstantSpectrum{10.0}, IsotropicPhase{}, std::nullopt, ConstantSpectrum{1.0}, true};
        lit_builder().medium(m, Source{"from-blender", "media.milky"});
      },
      "media.milky.absorption: at most 8 absorbers in a medium, its scatterers' own included");
  // A scattering world medium: refused by build(), before compile.
  expect_error(
      [&] {
        SceneBuilder b = lit_builder();
        MediumDesc fog;
        fog.name = "fog";
        fog.ior = ConstantIor{1.0};
        fog.scattering = ScatteringDesc{ConstantSpectrum{1.0}, IsotropicPhase{}, std::nullopt, std::nullopt, true};
        b.medium(fog, b.at("media.fog"));
        b.world_medium("fog", b.at("world_medium"));
        (void)std::move(b).build();
      },
      "built-in-code: world_medium: 'fog' scatters; the world medium cannot");
  // Objects: a transform that collapses the shape (a zero scale, as a Blender object scaled to 0),
  // a non-finite one, a priority beyond the range (a 64-bit value, not wrapped into an int).
  auto object_with = [&](Transform t, std::optional<std::int64_t> priority) {
    ObjectDesc o;
    o.shape = tetrahedron(0.01);
    o.inside = "glass";
    o.transform = t;
    o.priority = priority;
    lit_builder().object(o, Source{"from-blender", "objects[3]"});
  };
  expect_error([&] { object_with(Transform::scale({1, 0, 1}), std::nullopt); },
               "from-blender: objects[3].transform: the transform is singular (it collapses the shape)");
  expect_error([&] { object_with(Transform::translate({0, std::nan(""), 0}), std::nullopt); },
               "objects[3].transform: the transform is not finite");
  expect_error([&] { object_with(Transform{}, std::int64_t{1} << 40); },
               "objects[3].priority: must be between 0 and 1000000 (got 1099511627776)");
  expect_error(
      [&] {
        CameraDesc c;
        c.up = {0, std::nan(""), 0};
        lit_builder().camera(c, Source{"from-blender", "camera"});
      },
      "from-blender: camera.up: must be a direction of finite, non-zero length");
  // Transform steps as a front end gives them: each checked at its own place.
  const Source steps{"from-blender", "objects[0].transform"};
  expect_error([&] { (void)resolve_transform({ScaleStep{{1, 1, 0}}}, steps); },
               "objects[0].transform[0].scale: a scale of zero collapses the shape");
  expect_error([&] { (void)resolve_transform({TranslateStep{{1, 0, 0}}, RotateStep{30, {0, 0, 0}}}, steps); },
               "objects[0].transform[1].rotate_deg[1]: the rotation axis must not be zero");
  MatrixStep flat;
  flat.rows = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 1}}};
  expect_error([&] { (void)resolve_transform({flat}, steps); }, "objects[0].transform[0].matrix: the matrix is singular");
  flat.rows[2][2] = 1;
  flat.rows[3][3] = 2;
  expect_error([&] { (void)resolve_transform({flat}, steps); },
               "objects[0].transform[0].matrix[3]: the last row of an affine matrix must be [0, 0, 0, 1]");
  // And a good one composes in order: scale, then translate.
  const Transform t = resolve_transform({ScaleStep{{2, 2, 2}}, TranslateStep{{0, 1, 0}}}, steps);
  EXPECT_DOUBLE_EQ(t.apply({1, 0, 0}).x, 2.0);
  EXPECT_DOUBLE_EQ(t.apply({1, 0, 0}).y, 1.0);
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
