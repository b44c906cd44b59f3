#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "bouguer/core/error.h"
#include "bouguer/geometry/ray_scene.h"
#include "bouguer/geometry/shapes.h"
#include "bouguer/geometry/transform.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;

Mesh single(const Shape& s) {
  auto parts = make_shape(s, "test");
  EXPECT_EQ(parts.size(), 1u);
  return parts.front().mesh;
}

void expect_closed_with_volume(const Shape& s, double volume, double rel_tol, const char* what) {
  const Mesh m = single(s);
  // As compile checks it: positions welded (a crease of the shading normals keeps two vertices).
  EXPECT_EQ(closed_surface_problem(welded(m, 1e-12)), std::nullopt) << what;
  EXPECT_NEAR(signed_volume(m) / volume, 1.0, rel_tol) << what;
}

TEST(Shapes, ClosedShapesHaveTheirVolumes) {
  expect_closed_with_volume(BoxShape{{0.01, 0.004, 0.01}}, 4e-7, 1e-9, "box");
  const double hex_area = 1.5 * std::sqrt(3.0) * 0.02 * 0.02;
  expect_closed_with_volume(PyramidShape{6, 0.02, 0.012}, hex_area * 0.012 / 3.0, 1e-9, "pyramid");
  expect_closed_with_volume(PrismShape{6, 0.02, 0.012}, hex_area * 0.012, 1e-9, "prism");
  const double t = 0.29289321881345254;
  expect_closed_with_volume(TruncatedCubeShape{0.01, t}, 1e-6 * (1.0 - 8.0 * t * t * t / 6.0), 1e-9, "truncated cube");
  // Tessellated curved shapes: volume within the polygonal approximation's error.
  expect_closed_with_volume(SphereShape{0.01, 256}, 4.0 / 3.0 * kPi * 1e-6, 1e-3, "sphere");
  expect_closed_with_volume(CylinderShape{0.01, 0.02, 256}, kPi * 1e-4 * 0.02, 1e-3, "cylinder");
  expect_closed_with_volume(LatheShape{{{0, 0}, {0.01, 0}, {0.01, 0.02}, {0, 0.02}}, 256}, kPi * 1e-4 * 0.02, 1e-3,
                            "lathe");
}

TEST(Shapes, BrilliantIsAClosedGemWithManyFacets) {
  const Mesh m = single(BrilliantShape{});
  EXPECT_EQ(closed_surface_problem(m), std::nullopt);
  EXPECT_GT(signed_volume(m), 0.0);
  // Table on top at the expected height, pointed culet below.
  double top = -1, bottom = 1;
  for (const Vec3& p : m.positions) top = std::max(top, p.y), bottom = std::min(bottom, p.y);
  const double r = 0.005, g = 0.03 * 0.01 / 2;
  EXPECT_NEAR(top, g + (r - 0.57 * r) * std::tan(34.5 * kPi / 180.0), 1e-9);
  EXPECT_NEAR(bottom, -g - r * std::tan(40.75 * kPi / 180.0), 2e-5);
  EXPECT_GT(m.triangles.size(), 100u);
}

// A straight-walled cup: the glass shell and the liquid are both closed, and the liquid fills
// the given fraction of the inner height.
TEST(Shapes, VesselYieldsAClosedShellAndAClosedLiquid) {
  const VesselShape cup{{{0, 0}, {0.03, 0}, {0.03, 0.1}}, 0.002, 0.5, 128};
  const auto parts = make_shape(cup, "cup");
  ASSERT_EQ(parts.size(), 4u);
  Mesh shell, liquid;
  for (const auto& p : parts) {
    if (p.behind == Side::object) append(shell, p.mesh);
    if (p.behind == Side::contents) append(liquid, p.mesh);
    if (p.in_front == Side::contents) append(liquid, flipped(p.mesh));
  }
  shell = welded(shell, 1e-12);
  liquid = welded(liquid, 1e-12);
  EXPECT_EQ(closed_surface_problem(shell), std::nullopt);
  EXPECT_EQ(closed_surface_problem(liquid), std::nullopt);
  const double inner_r = 0.028, inner_h = 0.1 - 0.002;
  EXPECT_NEAR(signed_volume(liquid) / (kPi * inner_r * inner_r * inner_h * 0.5), 1.0, 1e-3);
  const double outer = kPi * 0.03 * 0.03 * 0.1, inner = kPi * inner_r * inner_r * inner_h;
  EXPECT_NEAR(signed_volume(shell) / (outer - inner), 1.0, 1e-3);
}

TEST(Shapes, ImpossibleParametersAreRefused) {
  EXPECT_THROW(make_shape(BoxShape{{0.01, -0.004, 0.01}}, "t"), Error);
  EXPECT_THROW(make_shape(PyramidShape{2, 0.02, 0.01}, "t"), Error);
  EXPECT_THROW(make_shape(TruncatedCubeShape{0.01, 0.6}, "t"), Error);
  EXPECT_THROW(make_shape(VesselShape{{{0, 0}, {0.001, 0}, {0.001, 0.1}}, 0.002, 0.5, 64}, "t"), Error);
  EXPECT_THROW(make_shape(MeshShape{"/nonexistent.obj"}, "t"), Error);
}

TEST(Shapes, ClosednessCheckFindsOpenFlippedAndInwardMeshes) {
  Mesh box = single(BoxShape{{1, 1, 1}});
  Mesh open = box;
  open.triangles.pop_back();
  EXPECT_NE(closed_surface_problem(open)->find("open"), std::string::npos);
  Mesh one_flipped = box;
  std::swap(one_flipped.triangles[0][1], one_flipped.triangles[0][2]);
  EXPECT_NE(closed_surface_problem(one_flipped), std::nullopt);
  EXPECT_NE(closed_surface_problem(flipped(box))->find("inward"), std::string::npos);
  // The counts: a box less one triangle has 3 boundary edges; one reversed triangle makes 3 edges
  // used twice in the same direction.
  EXPECT_EQ(*closed_surface_problem(open), "the surface is open (3 boundary edges); an interface must be closed");
  EXPECT_EQ(*closed_surface_problem(one_flipped),
            "3 edges are shared by faces of opposite orientation or by more than two faces");
}

// The welder's grid cells are wider than the tolerance: vertices within the tolerance merge also
// across a cell's faces, edges and corners (here at x, y, z = 0, where cells meet), and vertices
// farther apart stay apart.
TEST(Shapes, WelderMergesAcrossCellBoundariesOnlyWithinTheTolerance) {
  const double tol = 1e-3, e = 0.4 * tol;
  Mesh m;
  m.positions = {{-e, 5 * tol, 5 * tol}, {e, 5 * tol, 5 * tol},   // across x = 0: 0.8 tol apart
                 {5 * tol, -e, 5 * tol}, {5 * tol, e, 5 * tol},   // across y = 0
                 {-e, -e, -e},           {e, e, e},               // across a corner: 1.39 tol apart
                 {-e / 2, -e / 2, -e / 2},                         // 0.35 tol from the corner one
                 {9 * tol, 9 * tol, 9 * tol}, {9 * tol + 1.1 * tol, 9 * tol, 9 * tol}};  // 1.1 tol apart
  for (std::uint32_t i = 0; i + 2 < m.positions.size(); ++i) m.triangles.push_back({i, i + 1, i + 2});
  const Mesh w = welded(m, tol);
  // Merged: 1 into 0, 3 into 2, 6 into 4; 5 is 1.39 tol from 4, so it stays.
  EXPECT_EQ(w.positions.size(), 6u);
  EXPECT_EQ(w.positions[0], m.positions[0]);
  EXPECT_EQ(w.positions[1], m.positions[2]);
  EXPECT_EQ(w.positions[2], m.positions[4]);
}

TEST(Shapes, ObjAndPlyMeshesLoad) {
  const auto dir = test::scratch_dir("meshes");
  // A tetrahedron, outward faces.
  test::write_file(dir / "tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  test::write_file(dir / "tet.ply",
                   "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
                   "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  for (const char* f : {"tet.obj", "tet.ply"}) {
    const Mesh m = single(MeshShape{dir / f});
    EXPECT_EQ(closed_surface_problem(m), std::nullopt) << f;
    EXPECT_NEAR(signed_volume(m), 1.0 / 6.0, 1e-9) << f;
  }
  test::write_file(dir / "bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n");
  EXPECT_THROW(make_shape(MeshShape{dir / "bad.ply"}, "t"), Error);
}

// OBJ texture coordinates and normals: one mesh vertex per distinct (v, vt, vn) corner, so the
// UV seam at vertex 1 keeps both of its UVs; a file where some corners lack a vt keeps none.
TEST(Shapes, ObjKeepsUvsAndNormalsPerCorner) {
  const auto dir = test::scratch_dir("obj_uvs");
  test::write_file(dir / "quad.obj",
                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
                   "vn 0 0 2\nf 1/1/1 2/2/1 3/3/1\nf 1/5/1 3/3/1 4/4/1\n");
  const Mesh m = single(MeshShape{dir / "quad.obj"});
  ASSERT_EQ(m.positions.size(), 5u);
  ASSERT_EQ(m.uvs.size(), 5u);
  ASSERT_EQ(m.normals.size(), 5u);
  EXPECT_EQ(m.positions[m.triangles[1][0]], (Vec3{0, 0, 0}));
  EXPECT_EQ(m.uvs[m.triangles[0][0]], (std::array<double, 2>{0, 0}));
  EXPECT_EQ(m.uvs[m.triangles[1][0]], (std::array<double, 2>{0.5, 0.5}));
  EXPECT_EQ(m.uvs[m.triangles[1][2]], (std::array<double, 2>{0, 1}));
  EXPECT_EQ(m.normals[0], (Vec3{0, 0, 1}));  // made unit
  test::write_file(dir / "partial.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 3 4\n");
  const Mesh p = single(MeshShape{dir / "partial.obj"});
  EXPECT_TRUE(p.uvs.empty());
  EXPECT_TRUE(p.normals.empty());
  EXPECT_EQ(p.positions.size(), 4u);
}

TEST(Shapes, MirroringTransformKeepsFacesOutward) {
  const Mesh m = transformed(single(PyramidShape{5, 1, 1}), Transform::scale({-1, 1, 1}));
  EXPECT_EQ(closed_surface_problem(m), std::nullopt);
}

// The distance to a triangle in each of its seven Voronoi regions (face, three edges, three
// corners), in closed form, and for a degenerate triangle (a segment).
TEST(TriangleDistance, EveryRegionInClosedForm) {
  const Vec3 a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0};
  EXPECT_DOUBLE_EQ(triangle_distance({0.5, 0.5, 3}, a, b, c), 3.0);            // above the face
  EXPECT_DOUBLE_EQ(triangle_distance({0.5, 0.5, -0.25}, a, b, c), 0.25);       // below it
  EXPECT_DOUBLE_EQ(triangle_distance({1, -3, 4}, a, b, c), 5.0);               // edge ab
  EXPECT_DOUBLE_EQ(triangle_distance({-3, 1, 4}, a, b, c), 5.0);               // edge ac
  EXPECT_NEAR(triangle_distance({2, 2, 0}, a, b, c), std::sqrt(2.0), 1e-15);   // edge bc
  EXPECT_DOUBLE_EQ(triangle_distance({-3, -4, 0}, a, b, c), 5.0);              // corner a
  EXPECT_DOUBLE_EQ(triangle_distance({5, -4, 0}, a, b, c), 5.0);               // corner b
  EXPECT_DOUBLE_EQ(triangle_distance({0, 5, 4}, a, b, c), 5.0);                // corner c
  EXPECT_DOUBLE_EQ(triangle_distance({1, 0, 0}, a, b, c), 0.0);                // on an edge
  EXPECT_DOUBLE_EQ(triangle_distance({1, 1, 0}, a, b, {4, 0, 0}), 1.0);        // a segment: its middle
}

// RayScene's point query: over a closed box and a sphere mesh, the distance it finds is the least
// of triangle_distance over every triangle (brute force), at points inside, outside and on the
// surfaces; a radius below that distance is returned as it is. The nearest point it reports lies
// at that distance, and on one of the triangles (its own distance to the nearest one is 0).
TEST(RayScene, DistanceToSurfacesIsTheNearestTriangle) {
  RayScene scene;
  const Mesh box = single(BoxShape{{0.02, 0.01, 0.03}});
  Mesh ball = single(SphereShape{0.004, 24});
  ball = transformed(ball, Transform::translate({0.03, 0.0, 0.0}));
  scene.add(box);
  scene.add(ball);
  scene.commit();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.04, 0.04);
  for (int i = 0; i < 400; ++i) {
    const Vec3 p{u(rng), u(rng) * 0.5, u(rng)};
    double brute = 1e300;
    for (const Mesh* m : {&box, static_cast<const Mesh*>(&ball)})
      for (const auto& t : m->triangles)
        brute = std::min(brute, triangle_distance(p, m->positions[t[0]], m->positions[t[1]], m->positions[t[2]]));
    Vec3 nearest{7, 7, 7};
    EXPECT_DOUBLE_EQ(scene.distance_to_surfaces(p, 1.0, &nearest), brute) << i;
    EXPECT_NEAR(length(p - nearest), brute, 1e-15) << i;
    double on = 1e300;
    for (const Mesh* m : {&box, static_cast<const Mesh*>(&ball)})
      for (const auto& t : m->triangles)
        on = std::min(on, triangle_distance(nearest, m->positions[t[0]], m->positions[t[1]], m->positions[t[2]]));
    EXPECT_LT(on, 1e-15) << i;
    const Vec3 untouched{7, 7, 7};
    nearest = untouched;
    EXPECT_DOUBLE_EQ(scene.distance_to_surfaces(p, 0.5 * brute, &nearest), 0.5 * brute) << i;
    if (brute > 0.0) {
      EXPECT_TRUE(nearest == untouched) << i;
    }
  }
  EXPECT_DOUBLE_EQ(scene.distance_to_surfaces(box.positions[0], 1.0), 0.0);
}

// Rays through a 0.1 mm sliver of glass and across a 10 m room: every crossing is found, none twice.
TEST(RayScene, ThinSliversAndLargeScenesWithoutLeaksOrAcne) {
  RayScene scene;
  scene.add(single(BoxShape{{0.01, 0.0001, 0.01}}));                                            // sliver at origin
  scene.add(transformed(single(BoxShape{{10, 10, 10}}), Transform::translate({0, 0, 0})));  // room around it
  scene.commit();
  for (int i = 0; i < 200; ++i) {
    const double a = 0.002 * i / 200.0;
    Ray ray{{a, 1.0, -a}, normalize(Vec3{0.001 * i / 200.0, -1.0, 0.0005})};
    int crossings = 0;
    double travelled = 0.0;
    while (auto hit = scene.intersect(ray)) {
      travelled += hit->t;
      ++crossings;
      ray.origin = offset_ray_origin(*hit, ray.direction);
      if (crossings > 10) break;
    }
    EXPECT_EQ(crossings, 3) << "ray " << i;  // sliver top, sliver bottom, room floor
    EXPECT_NEAR(travelled, 6.0, 1e-3);
  }
}

// A hit interpolates the mesh's normals and UVs with Embree's barycentrics; where a mesh has none,
// the shading normal is the geometric one and the UVs are the barycentrics.
TEST(RayScene, HitsInterpolateNormalsAndUvs) {
  Mesh tri;
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.triangles = {{0, 1, 2}};
  Mesh with = tri;
  with.normals = {{0, 0, 1}, normalize(Vec3{1, 0, 1}), normalize(Vec3{0, 1, 1})};
  with.uvs = {{0.5, 0.5}, {1.5, 0.5}, {0.5, 2.5}};
  RayScene scene;
  scene.add(tri);
  scene.add(transformed(with, Transform::translate({0, 0, 1})));
  scene.commit();
  const Vec3 down{0, 0, -1};
  const auto near = scene.intersect(Ray{{0.25, 0.5, 2}, down});  // the one with attributes, at z = 1
  ASSERT_TRUE(near);
  EXPECT_EQ(near->geometry, 1u);
  EXPECT_NEAR(near->barycentric[0], 0.25, 1e-6);
  EXPECT_NEAR(near->barycentric[1], 0.5, 1e-6);
  EXPECT_NEAR(near->uv[0], 0.5 + 0.25, 1e-6);
  EXPECT_NEAR(near->uv[1], 0.5 + 2.0 * 0.5, 1e-6);
  const Vec3 n = normalize(Vec3{0, 0, 1} * 0.25 + normalize(Vec3{1, 0, 1}) * 0.25 + normalize(Vec3{0, 1, 1}) * 0.5);
  EXPECT_NEAR(length(near->shading_normal - n), 0.0, 1e-6);
  const auto far = scene.intersect(Ray{{0.25, 0.5, 0.5}, down});
  ASSERT_TRUE(far);
  EXPECT_EQ(far->geometry, 0u);
  EXPECT_NEAR(length(far->shading_normal - far->normal), 0.0, 1e-12);
  EXPECT_NEAR(far->uv[0], 0.25, 1e-6);
  EXPECT_NEAR(far->uv[1], 0.5, 1e-6);
}

// Normals go through the inverse transpose and stay on the geometric normal's side, mirrored or not.
TEST(Transform, NormalsFollowTheSurfaceUnderScaleAndMirror) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}};
  m.triangles = {{0, 1, 2}};
  m.normals.assign(3, normalize(cross(m.positions[1] - m.positions[0], m.positions[2] - m.positions[0])));
  for (const Vec3 s : {Vec3{1, 3, 0.5}, Vec3{-1, 2, 1}}) {
    const Mesh t = transformed(m, Transform::scale(s));
    const auto& tr = t.triangles[0];
    const Vec3 ng = normalize(cross(t.positions[tr[1]] - t.positions[tr[0]], t.positions[tr[2]] - t.positions[tr[0]]));
    for (const Vec3& n : t.normals) {
      EXPECT_NEAR(length(n), 1.0, 1e-12);
      EXPECT_NEAR(dot(n, ng), 1.0, 1e-12) << "a flat triangle's normal stays its geometric normal";
    }
  }
}

}  // namespace
}  // namespace bouguer
