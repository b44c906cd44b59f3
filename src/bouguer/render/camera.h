#pragma once
// Camera rays and camera importance. Film coordinates (x, y) in pixels, y down from the top;
// `fov_deg` / `width` span the shorter image side.
//
// Importance is normalised over the whole film (as pbrt): ∫ We = 1 over the image, so a light
// path splatted at its raster position adds to one pixel what the pixel's own importance (the
// number of pixels times We) gives, once the splats are divided by the samples per pixel.
//   pinhole: We = 1 / (A cos⁴θ), A the film's area at unit distance; the position is a delta.
//   orthographic: the direction is a delta (along the view), the origin uniform over the film's
//     area A in m², so We = 1 / A per unit area.
#include <array>
#include <optional>

#include "bouguer/geometry/ray_scene.h"
#include "bouguer/scene/description.h"

namespace bouguer {

// What a point in the scene sends to the camera: the direction from the point towards it, the
// distance to the lens (or the film plane, orthographic), where it lands on the film, and the
// factor We·|cos θ_camera| / (distance² · pdf of the camera's delta), to be multiplied by the
// path's throughput and f·|cos θ| at the point.
struct CameraConnection {
  Vec3 wi;
  double distance_m = 0.0;
  double film_x = 0.0, film_y = 0.0;
  double factor = 0.0;
};

struct Camera {
  CameraDesc desc;
  Vec3 forward, right, up;
  double half_extent = 1.0;  // tan(fov/2) (pinhole) or width/2 (orthographic)
  double film_area = 1.0;    // pinhole: at unit distance; orthographic: in m²

  explicit Camera(const CameraDesc& d);
  Ray generate_ray(double film_x, double film_y) const;

  // Importance of a camera ray (0 outside the film), and the densities generate_ray draws it
  // with when the film position is uniform: of its origin (per m²; 1 for the pinhole's delta)
  // and of its direction (per sr; 1 for the orthographic delta).
  double we(const Ray& ray) const;
  std::array<double, 2> pdf_we(const Ray& ray) const;
  // Where a world point appears on the film (nullopt: behind the camera or outside the image).
  std::optional<std::array<double, 2>> film_position(const Vec3& point_m) const;
  std::optional<CameraConnection> connect(const Vec3& point_m) const;
  // The ray cone of one pixel (scene/texture.h): its width at the camera (orthographic: the
  // pixel's size) and its spread angle (pinhole: the angle one pixel subtends at the centre).
  struct Cone {
    double width_m = 0.0, spread_rad = 0.0;
  };
  Cone pixel_cone() const;
};

}  // namespace bouguer
