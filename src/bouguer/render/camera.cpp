#include "bouguer/render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bouguer {

Camera::Camera(const CameraDesc& d) : desc(d) {
  forward = normalize(d.look_at_m - d.position_m);
  right = normalize(cross(forward, d.up));
  up = cross(right, forward);
  half_extent = d.type == CameraType::pinhole ? std::tan(d.fov_deg * std::numbers::pi / 360.0) : d.width_m / 2.0;
  const double shorter = std::min(d.width_px, d.height_px);
  film_area = (2.0 * half_extent * d.width_px / shorter) * (2.0 * half_extent * d.height_px / shorter);
}

Ray Camera::generate_ray(double film_x, double film_y) const {
  const double shorter = std::min(desc.width_px, desc.height_px);
  const double sx = ((2.0 * film_x - desc.width_px) / shorter + 2.0 * desc.shift_x) * half_extent;
  const double sy = ((desc.height_px - 2.0 * film_y) / shorter + 2.0 * desc.shift_y) * half_extent;
  if (desc.type == CameraType::orthographic) return {desc.position_m + right * sx + up * sy, forward};
  return {desc.position_m, normalize(forward + right * sx + up * sy)};
}

std::optional<std::array<double, 2>> Camera::film_position(const Vec3& point_m) const {
  const Vec3 d = point_m - desc.position_m;
  const double depth = dot(d, forward);
  if (!(depth > 0.0)) return std::nullopt;
  // Film-plane coordinates: at unit distance (pinhole) or in metres (orthographic).
  const double scale = desc.type == CameraType::pinhole ? 1.0 / depth : 1.0;
  const double sx = dot(d, right) * scale, sy = dot(d, up) * scale;
  const double shorter = std::min(desc.width_px, desc.height_px);
  const double x = ((sx / half_extent - 2.0 * desc.shift_x) * shorter + desc.width_px) / 2.0;
  const double y = (desc.height_px - (sy / half_extent - 2.0 * desc.shift_y) * shorter) / 2.0;
  if (!(x >= 0.0 && x < desc.width_px && y >= 0.0 && y < desc.height_px)) return std::nullopt;
  return std::array{x, y};
}

double Camera::we(const Ray& ray) const {
  const double cos_theta = dot(ray.direction, forward);
  if (desc.type == CameraType::orthographic) return cos_theta > 1.0 - 1e-12 ? 1.0 / film_area : 0.0;
  if (!(cos_theta > 0.0) || !film_position(desc.position_m + ray.direction)) return 0.0;
  return 1.0 / (film_area * cos_theta * cos_theta * cos_theta * cos_theta);
}

std::array<double, 2> Camera::pdf_we(const Ray& ray) const {
  if (desc.type == CameraType::orthographic) return {1.0 / film_area, 1.0};
  const double cos_theta = dot(ray.direction, forward);
  if (!(cos_theta > 0.0)) return {1.0, 0.0};
  return {1.0, 1.0 / (film_area * cos_theta * cos_theta * cos_theta)};
}

std::optional<CameraConnection> Camera::connect(const Vec3& point_m) const {
  const auto film = film_position(point_m);
  if (!film) return std::nullopt;
  CameraConnection c;
  c.film_x = (*film)[0];
  c.film_y = (*film)[1];
  if (desc.type == CameraType::orthographic) {
    c.wi = -forward;
    c.distance_m = dot(point_m - desc.position_m, forward);
    c.factor = 1.0 / film_area;  // the projection's dA_film = |cos θ| dA at the point
    return c;
  }
  const Vec3 to = desc.position_m - point_m;
  c.distance_m = length(to);
  c.wi = to / c.distance_m;
  const double cos_theta = dot(-c.wi, forward);
  // We · cos θ_camera / d²: the pinhole's delta position turned into a solid angle at the point.
  c.factor = 1.0 / (film_area * cos_theta * cos_theta * cos_theta * c.distance_m * c.distance_m);
  return c;
}

Camera::Cone Camera::pixel_cone() const {
  const double pixel = 2.0 * half_extent / std::min(desc.width_px, desc.height_px);
  if (desc.type == CameraType::orthographic) return {pixel, 0.0};
  return {0.0, 2.0 * std::atan(pixel / 2.0)};
}

}  // namespace bouguer
