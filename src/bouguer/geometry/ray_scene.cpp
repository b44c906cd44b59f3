#include "bouguer/geometry/ray_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "bouguer/core/error.h"

namespace bouguer {

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<Mesh> meshes;

  Impl() {
    device = rtcNewDevice(nullptr);
    if (!device) fail("cannot start Embree (error {})", static_cast<int>(rtcGetDeviceError(nullptr)));
    scene = rtcNewScene(device);
    // Robust mode: watertight triangle tests, so rays never slip between shared edges.
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  }
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

RayScene::RayScene() : impl_(std::make_unique<Impl>()) {}
RayScene::~RayScene() = default;
RayScene::RayScene(RayScene&&) noexcept = default;
RayScene& RayScene::operator=(RayScene&&) noexcept = default;

std::uint32_t RayScene::add(const Mesh& mesh) {
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.positions.size()));
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(mesh.positions[i][k]);
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i][k];
  rtcCommitGeometry(g);
  const unsigned id = rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  impl_->meshes.push_back(mesh);
  return id;
}

void RayScene::commit() { rtcCommitScene(impl_->scene); }

const Mesh& RayScene::mesh(std::uint32_t geometry) const { return impl_->meshes[geometry]; }

std::optional<Hit> RayScene::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(ray.origin.x);
  rh.ray.org_y = static_cast<float>(ray.origin.y);
  rh.ray.org_z = static_cast<float>(ray.origin.z);
  rh.ray.dir_x = static_cast<float>(ray.direction.x);
  rh.ray.dir_y = static_cast<float>(ray.direction.y);
  rh.ray.dir_z = static_cast<float>(ray.direction.z);
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = std::isinf(ray.t_max) ? std::numeric_limits<float>::infinity() : static_cast<float>(ray.t_max);
  rh.ray.mask = 0xffffffffu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

  const Mesh& m = impl_->meshes[rh.hit.geomID];
  const auto& tri = m.triangles[rh.hit.primID];
  const Vec3 &p0 = m.positions[tri[0]], &p1 = m.positions[tri[1]], &p2 = m.positions[tri[2]];
  Hit h;
  h.t = rh.ray.tfar;
  h.geometry = rh.hit.geomID;
  h.primitive = rh.hit.primID;
  h.point = p0 * (1.0 - rh.hit.u - rh.hit.v) + p1 * double(rh.hit.u) + p2 * double(rh.hit.v);
  h.normal = normalize(cross(p1 - p0, p2 - p0));
  const double b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1.0 - b1 - b2;
  h.barycentric = {b1, b2};
  h.shading_normal = h.normal;
  if (!m.normals.empty()) {
    const Vec3 n = m.normals[tri[0]] * b0 + m.normals[tri[1]] * b1 + m.normals[tri[2]] * b2;
    const double l = length(n);
    // Opposite vertex normals can cancel; a shading normal is never on the far side of the face.
    if (l > 1e-12 && dot(n, h.normal) > 0.0) h.shading_normal = n / l;
  }
  if (!m.uvs.empty()) {
    const auto &t0 = m.uvs[tri[0]], &t1 = m.uvs[tri[1]], &t2 = m.uvs[tri[2]];
    h.uv = {b0 * t0[0] + b1 * t1[0] + b2 * t2[0], b0 * t0[1] + b1 * t1[1] + b2 * t2[1]};
  } else {
    h.uv = {b1, b2};
  }
  return h;
}

}  // namespace bouguer
