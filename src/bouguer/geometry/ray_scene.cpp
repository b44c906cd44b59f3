#include "bouguer/geometry/ray_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "bouguer/core/error.h"

namespace bouguer {
namespace {

// An analytic geometry as Embree's user data: the shape, its frames and its world box.
struct AnalyticRecord {
  AnalyticShape shape;
  Mat3 to_local;         // inverse of the linear part
  Mat3 normal_to_world;  // its transpose: normals go by the inverse transpose
  unsigned geometry = RTC_INVALID_GEOMETRY_ID;
  std::array<Vec3, 2> world_bounds;
  double min_stretch = 1.0;  // the linear part's smallest singular value (a hair less)
};

// The smallest singular value of the linear part a, as 1/σ_max(a⁻¹): the square root of the
// largest eigenvalue of the symmetric a⁻ᵀa⁻¹, in closed form (Smith 1961, "Eigenvalues of a
// symmetric 3 × 3 matrix"), which is well conditioned however unequal the stretches are; made a
// hair smaller so that rounding never puts it above the true value.
double smallest_stretch(const Mat3& to_local) {
  double s[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      s[i][j] = to_local.m[0][i] * to_local.m[0][j] + to_local.m[1][i] * to_local.m[1][j] + to_local.m[2][i] * to_local.m[2][j];
  const double off = s[0][1] * s[0][1] + s[0][2] * s[0][2] + s[1][2] * s[1][2];
  const double q = (s[0][0] + s[1][1] + s[2][2]) / 3.0;
  const double p2 = (s[0][0] - q) * (s[0][0] - q) + (s[1][1] - q) * (s[1][1] - q) + (s[2][2] - q) * (s[2][2] - q) + 2.0 * off;
  double largest;
  if (p2 <= 1e-30 * q * q) {
    largest = std::max({s[0][0], s[1][1], s[2][2]});
  } else {
    const double p = std::sqrt(p2 / 6.0);
    double b[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) b[i][j] = (s[i][j] - (i == j ? q : 0.0)) / p;
    const double det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                       b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
    largest = q + 2.0 * p * std::cos(std::acos(std::clamp(det / 2.0, -1.0, 1.0)) / 3.0);
  }
  if (!(largest > 0.0) || !std::isfinite(largest)) return 0.0;
  return (1.0 - 1e-9) / std::sqrt(largest);
}

// A point query's state: the double-precision point, the nearest distance so far, and the
// geometry (meshes by id, analytic records by id).
struct DistanceQuery {
  Vec3 p;
  double best;
  double pad;  // the float point's error
  const std::vector<Mesh>* meshes;
  const std::vector<std::unique_ptr<AnalyticRecord>>* analytic;
  unsigned geometry = RTC_INVALID_GEOMETRY_ID, primitive = 0;  // the nearest found so far
};

bool distance_callback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<DistanceQuery*>(args->userPtr);
  double d;
  if (const auto& r = (*q->analytic)[args->geomID]) {
    d = distance_local(r->shape.surface, r->to_local * (q->p - r->shape.to_world.translation)) * r->min_stretch;
  } else {
    const Mesh& m = (*q->meshes)[args->geomID];
    const auto& tri = m.triangles[args->primID];
    const Vec3 &a = m.positions[tri[0]], &b = m.positions[tri[1]], &c = m.positions[tri[2]];
    // The distance to the triangle's plane bounds the distance to the triangle from below: a
    // triangle whose plane is farther than the nearest so far, by more than the pad that covers
    // Embree's rounding, is not it. Not for slivers, whose plane rounding tilts.
    const Vec3 ab = b - a, ac = c - a, n = cross(ab, ac);
    const double n2 = dot(n, n), h = dot(q->p - a, n), longest2 = std::max(dot(ab, ab), dot(ac, ac));
    const double beyond = q->best + q->pad;
    if (n2 > 1e-12 * longest2 * longest2 && h * h > beyond * beyond * n2) return false;
    d = triangle_distance(q->p, a, b, c);
  }
  if (!(d < q->best)) return false;
  q->best = d;
  q->geometry = args->geomID;
  q->primitive = args->primID;
  // Embree culls with its float point and radius: padded so that no nearer primitive is culled.
  args->query->radius = std::nextafter(static_cast<float>(d * (1.0 + 1e-6) + q->pad), INFINITY);
  return true;
}

// Embree's context extended with the query's double-precision ray (Embree's is float) and the
// analytic hit last accepted, which is the nearest analytic one: each accepted hit shortens tfar.
struct QueryContext {
  RTCIntersectContext embree;  // first, so Embree's context pointer is this struct's
  const Ray* ray = nullptr;
  LocalHit analytic;
  unsigned analytic_geometry = RTC_INVALID_GEOMETRY_ID;
};

Mat3 transpose(const Mat3& a) {
  Mat3 t;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t.m[i][j] = a.m[j][i];
  return t;
}

std::array<Vec3, 2> world_bounds(const AnalyticShape& shape) {
  const auto [lo, hi] = local_bounds(shape.surface);
  Vec3 wlo{1e300, 1e300, 1e300}, whi = -wlo;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p = shape.to_world.apply({corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z});
    for (std::size_t i = 0; i < 3; ++i) wlo[i] = std::min(wlo[i], p[i]), whi[i] = std::max(whi[i], p[i]);
  }
  return {wlo, whi};
}

// The ray in the shape's local frame, unnormalised, so that t is the world ray's t.
std::optional<LocalHit> intersect_record(const AnalyticRecord& r, const Ray& ray, double t_max) {
  const Vec3 o = r.to_local * (ray.origin - r.shape.to_world.translation);
  return intersect_local(r.shape.surface, o, r.to_local * ray.direction, 0.0, t_max);
}

void analytic_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* r = static_cast<const AnalyticRecord*>(args->geometryUserPtr);
  // Rounded outwards to float, and padded a little more for Embree's own float arithmetic.
  auto down = [](double x) { return std::nextafter(static_cast<float>(x - 1e-7 * std::abs(x)), -INFINITY); };
  auto up = [](double x) { return std::nextafter(static_cast<float>(x + 1e-7 * std::abs(x)), INFINITY); };
  const auto& [lo, hi] = r->world_bounds;
  *args->bounds_o = RTCBounds{down(lo.x), down(lo.y), down(lo.z), 0.0f, up(hi.x), up(hi.y), up(hi.z), 0.0f};
}

void analytic_intersect(const RTCIntersectFunctionNArguments* args) {
  if (args->N != 1 || !args->valid[0]) return;  // RayScene traces single rays only
  auto* context = reinterpret_cast<QueryContext*>(args->context);
  const auto* r = static_cast<const AnalyticRecord*>(args->geometryUserPtr);
  auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  // The double t_max while nothing is hit (tfar is it rounded to float), tfar after.
  const double t_max = std::min(context->ray->t_max, static_cast<double>(rh->ray.tfar));
  const auto h = intersect_record(*r, *context->ray, t_max);
  if (!h) return;
  rh->ray.tfar = static_cast<float>(h->t);
  const Vec3 n = r->normal_to_world * h->normal;
  rh->hit.Ng_x = static_cast<float>(n.x), rh->hit.Ng_y = static_cast<float>(n.y), rh->hit.Ng_z = static_cast<float>(n.z);
  rh->hit.u = 0.0f, rh->hit.v = 0.0f;
  rh->hit.primID = static_cast<unsigned>(h->part);
  rh->hit.geomID = r->geometry;
  rh->hit.instID[0] = args->context->instID[0];
  context->analytic = *h;
  context->analytic_geometry = r->geometry;
}

Hit analytic_hit(const AnalyticRecord& r, const LocalHit& local) {
  Hit h;
  h.t = local.t;
  h.geometry = r.geometry;
  h.primitive = static_cast<std::uint32_t>(local.part);
  h.point = r.shape.to_world.apply(local.point);
  h.normal = normalize(r.normal_to_world * local.normal);
  h.shading_normal = h.normal;
  h.uv = local.uv;
  return h;
}

}  // namespace

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<Mesh> meshes;                                // by geometry id; empty for analytic ones
  std::vector<std::unique_ptr<AnalyticRecord>> analytic;  // by geometry id; null for meshes (fixed addresses for Embree)
  double extent_m = 0.0;  // the largest absolute coordinate of the committed scene's box

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
  impl_->analytic.emplace_back();
  return id;
}

std::uint32_t RayScene::add(const AnalyticShape& shape) {
  auto record = std::make_unique<AnalyticRecord>();
  record->shape = shape;
  record->to_local = inverse(shape.to_world.linear);
  record->normal_to_world = transpose(record->to_local);
  record->world_bounds = world_bounds(shape);
  record->min_stretch = smallest_stretch(record->to_local);
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, 1);
  rtcSetGeometryUserData(g, record.get());
  rtcSetGeometryBoundsFunction(g, analytic_bounds, nullptr);
  rtcSetGeometryIntersectFunction(g, analytic_intersect);
  rtcCommitGeometry(g);
  record->geometry = rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  impl_->meshes.emplace_back();
  impl_->analytic.push_back(std::move(record));
  return impl_->analytic.back()->geometry;
}

void RayScene::commit() {
  rtcCommitScene(impl_->scene);
  RTCBounds b;
  rtcGetSceneBounds(impl_->scene, &b);
  impl_->extent_m = 0.0;
  for (const float c : {b.lower_x, b.lower_y, b.lower_z, b.upper_x, b.upper_y, b.upper_z})
    if (std::isfinite(c)) impl_->extent_m = std::max(impl_->extent_m, static_cast<double>(std::abs(c)));
}

const Mesh& RayScene::mesh(std::uint32_t geometry) const { return impl_->meshes[geometry]; }
const AnalyticShape* RayScene::analytic(std::uint32_t geometry) const {
  const auto& r = impl_->analytic[geometry];
  return r ? &r->shape : nullptr;
}

std::array<Vec3, 2> RayScene::bounds(std::uint32_t geometry) const {
  if (const auto& r = impl_->analytic[geometry]) return r->world_bounds;
  Vec3 lo{1e300, 1e300, 1e300}, hi = -lo;
  for (const Vec3& p : impl_->meshes[geometry].positions)
    for (std::size_t i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
  return {lo, hi};
}

double RayScene::rounding_scale_m(const Vec3& p) const {
  return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), impl_->extent_m, 1e-3});
}

double RayScene::distance_to_surfaces(const Vec3& p, double radius_m, Vec3* nearest, std::uint32_t* geometry) const {
  // Embree culls with its float point and the tree's float boxes: the pad covers their rounding.
  DistanceQuery q{p, radius_m, 1e-6 * rounding_scale_m(p), &impl_->meshes, &impl_->analytic};
  RTCPointQuery query;
  query.x = static_cast<float>(p.x), query.y = static_cast<float>(p.y), query.z = static_cast<float>(p.z);
  query.time = 0.0f;
  // The float point is up to half an ulp of the largest coordinate off: the radius covers that.
  query.radius = static_cast<float>(radius_m * (1.0 + 1e-6) + q.pad);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &query, &context, distance_callback, &q);
  if (geometry && q.geometry != RTC_INVALID_GEOMETRY_ID) *geometry = q.geometry;
  if (nearest && q.geometry != RTC_INVALID_GEOMETRY_ID) {
    if (const auto& r = impl_->analytic[q.geometry]) {
      const Vec3 local = r->to_local * (p - r->shape.to_world.translation);
      *nearest = r->shape.to_world.apply(nearest_local(r->shape.surface, local));
    } else {
      const Mesh& m = impl_->meshes[q.geometry];
      const auto& tri = m.triangles[q.primitive];
      *nearest = p - triangle_offset(p, m.positions[tri[0]], m.positions[tri[1]], m.positions[tri[2]]);
    }
  }
  return std::max(0.0, q.best);
}

std::optional<Hit> RayScene::intersect(const Ray& ray) const {
  QueryContext context;
  rtcInitIntersectContext(&context.embree);
  context.ray = &ray;
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
  rtcIntersect1(impl_->scene, &context.embree, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  if (rh.hit.geomID == context.analytic_geometry) return analytic_hit(*impl_->analytic[rh.hit.geomID], context.analytic);

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
