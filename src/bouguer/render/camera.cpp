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
}

Ray Camera::generate_ray(double film_x, double film_y) const {
  const double shorter = std::min(desc.width_px, desc.height_px);
  const double sx = (2.0 * film_x - desc.width_px) / shorter * half_extent;
  const double sy = (desc.height_px - 2.0 * film_y) / shorter * half_extent;
  if (desc.type == CameraType::orthographic) return {desc.position_m + right * sx + up * sy, forward};
  return {desc.position_m, normalize(forward + right * sx + up * sy)};
}

}  // namespace bouguer
