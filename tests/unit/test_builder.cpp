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
  lamp.emission = EmissionDesc{ConstantSpectrum{1.0}, true, std::nullopt};
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

}  // namespace
}  // namespace bouguer
