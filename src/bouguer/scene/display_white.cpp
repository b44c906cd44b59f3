#include "bouguer/scene/display_white.h"

#include <map>
#include <numbers>
#include <variant>

#include "bouguer/lights/environment.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

// The mean linear Rec.709 colour of a map over the sphere (each texel by its solid angle, ∝ sin θ).
Vec3 environment_mean_xyz(const EnvironmentMap& map) {
  Vec3 sum{};
  for (int row = 0; row < map.height; ++row) {
    const double sin_theta = std::sin((row + 0.5) / map.height * std::numbers::pi);
    for (int col = 0; col < map.width; ++col) {
      const Vec3f& c = map.rgb[static_cast<std::size_t>(row) * map.width + col];
      sum += Vec3{c.x, c.y, c.z} * sin_theta;
    }
  }
  return rgb_to_xyz_matrix(kRec709) * sum;
}

// The XYZ of a light's own colour, at any luminance.
std::optional<Vec3> light_xyz(const RenderScene& scene, const Light& light) {
  const int id = std::visit(
      [](const auto& l) -> int {
        using L = std::decay_t<decltype(l)>;
        if constexpr (std::is_same_v<L, AreaLight> || std::is_same_v<L, SphereLight> ||
                      std::is_same_v<L, BackgroundLight>)
          return l.radiance;
        else if constexpr (std::is_same_v<L, PointLight> || std::is_same_v<L, SpotLight>)
          return l.intensity;
        else if constexpr (std::is_same_v<L, DistantLight>)
          return l.irradiance;
        else
          return -1;
      },
      light);
  if (const auto* env = std::get_if<EnvironmentLight>(&light)) return environment_mean_xyz(*env->map);
  if (id < 0) return std::nullopt;
  const auto* spectrum = std::get_if<Spectrum>(&scene.spectra[static_cast<std::size_t>(id)].source);
  if (!spectrum) return std::nullopt;
  return spectrum_to_xyz(*spectrum);
}

}  // namespace

std::optional<Vec3> brightest_emitter_white_xyz(const RenderScene& scene) {
  // An emitting mesh is one light per triangle: its triangles' powers are summed (by their
  // spectrum, which they share), so that a large softbox outweighs a small lamp as it should.
  std::map<int, double> mesh_power;
  for (std::size_t i = 0; i < scene.lights.size(); ++i)
    if (const auto* a = std::get_if<AreaLight>(&scene.lights[i])) mesh_power[a->radiance] += scene.light_power[i];
  std::size_t brightest = scene.lights.size();
  double most = 0.0;
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const auto* a = std::get_if<AreaLight>(&scene.lights[i]);
    const double power = a ? mesh_power[a->radiance] : scene.light_power[i];
    if (power > most) most = power, brightest = i;
  }
  if (brightest == scene.lights.size()) return std::nullopt;
  const std::optional<Vec3> xyz = light_xyz(scene, scene.lights[brightest]);
  if (!xyz || !(xyz->y > 0.0)) return std::nullopt;
  return *xyz / xyz->y;
}

DisplayTransform display_transform(const RenderScene& scene, const DisplayDesc& d, const Film& film) {
  std::optional<Vec3> emitter;
  if (std::holds_alternative<BrightestEmitterWhite>(d.white_balance)) emitter = brightest_emitter_white_xyz(scene);
  return resolve_display(d, film, emitter);
}

}  // namespace bouguer
