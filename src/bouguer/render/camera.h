#pragma once
// Camera rays. Film coordinates (x, y) in pixels, y down from the top; `fov_deg` / `width` span the
// shorter image side.
#include "bouguer/geometry/ray_scene.h"
#include "bouguer/scene/description.h"

namespace bouguer {

struct Camera {
  CameraDesc desc;
  Vec3 forward, right, up;
  double half_extent = 1.0;  // tan(fov/2) (pinhole) or width/2 (orthographic)

  explicit Camera(const CameraDesc& d);
  Ray generate_ray(double film_x, double film_y) const;
};

}  // namespace bouguer
