#include "bouguer/scene/builder.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/io/limits.h"
#include "bouguer/media/medium.h"

namespace bouguer {

const std::vector<MediumDesc>& predefined_media() {
  static const std::vector<MediumDesc> media = {{"vacuum", ConstantIor{1.0}, ConstantSpectrum{0.0}, false, {}, {}},
                                                {"air", ConstantIor{1.000293}, ConstantSpectrum{0.0}, false, {}, {}}};
  return media;
}

namespace {
bool is_predefined(const std::string& name) {
  for (const MediumDesc& m : predefined_media())
    if (m.name == name) return true;
  return false;
}

}  // namespace

SceneBuilder::SceneBuilder(std::filesystem::path source) { desc_.file = std::move(source); }

void SceneBuilder::fail_at(const std::string& where, const std::string& problem) const {
  fail("{}: {}: {}", desc_.file.string(), where.empty() ? "(top level)" : where, problem);
}

void SceneBuilder::refer_to_medium(const std::string& name, const std::string& where) {
  medium_refs_.emplace_back(name, where);
}

SceneBuilder& SceneBuilder::camera(const CameraDesc& c, const std::string& where) {
  if (c.type == CameraType::pinhole && !(c.fov_deg > 0.0 && c.fov_deg < 180.0))
    fail_at(where + ".fov_deg", "must be between 0 and 180 degrees");
  if (c.type == CameraType::orthographic && !(c.width_m > 0.0)) fail_at(where + ".width", "must be a positive length");
  if (c.width_px < 1 || c.height_px < 1 || c.width_px > 16384 || c.height_px > 16384)
    fail_at(where + ".resolution", fmt::format("each side must be 1 to 16384 pixels (got {}x{})", c.width_px, c.height_px));
  const Vec3 forward = c.look_at_m - c.position_m;
  if (length(forward) == 0.0) fail_at(where, "'position' and 'look_at' coincide");
  if (length(c.up) == 0.0 || length(cross(normalize(forward), normalize(c.up))) < 1e-9)
    fail_at(where + ".up", "'up' must not be zero or parallel to the view direction");
  desc_.camera = c;
  return *this;
}

SceneBuilder& SceneBuilder::settings(const RenderSettings& s, const std::string& where) {
  if (s.spp < 1 || s.spp > (1 << 20)) fail_at(where + ".spp", fmt::format("must be between 1 and {}", 1 << 20));
  if (s.max_depth < 1 || s.max_depth > 1000) fail_at(where + ".max_depth", "must be between 1 and 1000");
  desc_.render = s;
  return *this;
}

SceneBuilder& SceneBuilder::world_medium(const std::string& name, const std::string& where) {
  desc_.world_medium = name;
  refer_to_medium(name, where);
  return *this;
}

SceneBuilder& SceneBuilder::medium(MediumDesc m, const std::string& where) {
  if (is_predefined(m.name)) fail_at(where, fmt::format("'{}' is predefined; choose another name", m.name));
  if (desc_.media.contains(m.name)) fail_at(where, fmt::format("a medium named '{}' exists already", m.name));
  if (const auto problem = beyond_limit(m.sigma_a_per_m, kMaxCoefficientPerM, "the absorption coefficient σ_a (per metre)"))
    fail_at(where + ".absorption", *problem);
  if (m.field_absorbers.size() > kMaxAbsorbersPerMedium)
    fail_at(where + ".absorption", fmt::format("at most {} absorbers per medium (got {})", kMaxAbsorbersPerMedium,
                                               m.field_absorbers.size()));
  for (std::size_t i = 0; i < m.field_absorbers.size(); ++i) {
    const FieldAbsorberDesc& a = m.field_absorbers[i];
    const std::string at = m.field_absorbers.size() > 1 ? fmt::format("{}.absorption[{}]", where, i) : where + ".absorption";
    if (const auto problem = beyond_limit(a.epsilon_per_m, kMaxCoefficientPerM, "σ_a per unit concentration"))
      fail_at(at, *problem);
    if (min_value(a.epsilon_per_m) < 0.0) fail_at(at, "σ_a must not be negative");
    // A linear field grows without bound; its column densities are capped (concentration_field.h).
    const double peak = max_concentration(a.field);
    if (std::isfinite(peak) && !(peak * max_value(a.epsilon_per_m) <= kMaxCoefficientPerM))
      fail_at(at + ".concentration", fmt::format("σ_a at the field's largest concentration ({:g}) exceeds {:g} per metre",
                                                 peak, kMaxCoefficientPerM));
  }
  if (m.scattering) {
    const std::string at = where + ".scattering";
    if (const auto problem = beyond_limit(m.scattering->sigma_s_per_m, kMaxCoefficientPerM, "the scattering coefficient σ_s (per metre)"))
      fail_at(at, *problem);
    if (min_value(m.scattering->sigma_s_per_m) < 0.0) fail_at(at, "σ_s must not be negative");
    if (m.scattering->sigma_a_per_m && min_value(*m.scattering->sigma_a_per_m) < 0.0)
      fail_at(at, "the scatterers' σ_a must not be negative");
    if (const auto* hg = std::get_if<HenyeyGreensteinPhase>(&m.scattering->phase); hg && !(std::abs(hg->g) < 1.0))
      fail_at(at + ".phase.g", fmt::format("must lie strictly between −1 and 1 (got {})", hg->g));
    if (m.scattering->density) {
      const double peak = max_concentration(*m.scattering->density);
      const double sigma = std::max(max_value(m.scattering->sigma_s_per_m), max_value(m.sigma_a_per_m));
      if (std::isfinite(peak) && !(peak * sigma <= kMaxCoefficientPerM))
        fail_at(at + ".density", fmt::format("σ at the density's largest value ({:g}) exceeds {:g} per metre", peak,
                                             kMaxCoefficientPerM));
      if (m.scattering->density_scales_absorption)
        for (const FieldAbsorberDesc& a : m.field_absorbers)
          if (!std::holds_alternative<ConstantField>(a.field))
            fail_at(where + ".absorption", "with a scattering density, the absorption's concentration must be a number");
    }
  }
  const std::string name = m.name;
  desc_.media[name] = std::move(m);
  return *this;
}

SceneBuilder& SceneBuilder::object(ObjectDesc o, const std::string& where) {
  const int roles = int(o.inside.has_value()) + int(o.emission.has_value()) + int(o.material.has_value());
  if (roles != 1) fail_at(where, "give exactly one of 'inside' (a medium interface), 'emission' or 'material'");
  if (!o.inside && (o.outside || o.contents || o.roughness != 0.0))
    fail_at(where, "'outside', 'contents' and 'roughness' belong to interfaces ('inside')");
  if (!(o.roughness >= 0.0 && o.roughness <= 1.0))
    fail_at(where + ".roughness", fmt::format("a GGX roughness (alpha) must be between 0 and 1 (got {})", o.roughness));
  const bool vessel = std::holds_alternative<VesselShape>(o.shape);
  if (vessel && o.inside && !o.contents && std::get<VesselShape>(o.shape).fill > 0.0)
    fail_at(where, "a filled vessel needs 'contents' (the liquid's medium)");
  if (!vessel && o.contents) fail_at(where + ".contents", "only a vessel has contents");
  if (o.emission)
    if (const auto problem = beyond_limit(o.emission->radiance, kMaxEmission, "the emitted radiance"))
      fail_at(where + ".emission", *problem);
  if (o.inside) refer_to_medium(*o.inside, where + ".inside");
  if (o.outside) refer_to_medium(*o.outside, where + ".outside");
  if (o.contents) refer_to_medium(*o.contents, where + ".contents");
  desc_.objects.push_back(std::move(o));
  return *this;
}

SceneBuilder& SceneBuilder::light(const DeltaLightDesc& l, const std::string& where) {
  if (l.type != DeltaLightType::point && std::abs(length(l.direction) - 1.0) > 1e-9)
    fail_at(where, "the light's direction must be a unit vector");
  if (l.type == DeltaLightType::spot) {
    if (!(l.cone_deg > 0.0 && l.cone_deg <= 90.0)) fail_at(where + ".cone_deg", "must be between 0 and 90 degrees");
    if (!(l.falloff_deg >= 0.0 && l.falloff_deg <= l.cone_deg))
      fail_at(where + ".falloff_deg", "must be between 0 and cone_deg");
  }
  if (l.radius_m != 0.0 && (l.type != DeltaLightType::spot || !(l.radius_m > 0.0)))
    fail_at(where + ".radius", "only a spot light takes a radius, and it must be a positive length");
  if (const auto problem = beyond_limit(l.intensity, kMaxEmission, "the light's intensity")) fail_at(where, *problem);
  desc_.lights.push_back(l);
  return *this;
}

SceneBuilder& SceneBuilder::background(const EmissionDesc& e, const std::string& where) {
  if (const auto problem = beyond_limit(e.radiance, kMaxEmission, "the background's radiance")) fail_at(where, *problem);
  desc_.background = e;
  desc_.environment.reset();
  return *this;
}

SceneBuilder& SceneBuilder::environment(const EnvironmentDesc& e, const std::string& where) {
  if (!(e.scale >= 0.0 && e.scale <= kMaxEnvironmentRadiance))
    fail_at(where + ".scale", fmt::format("must be between 0 and {:g} (got {})", kMaxEnvironmentRadiance, e.scale));
  desc_.environment = e;
  return *this;
}

SceneDesc SceneBuilder::build() && {
  std::vector<std::string> names;
  for (const MediumDesc& m : predefined_media()) names.push_back(m.name);
  for (const auto& [name, m] : desc_.media) names.push_back(name);
  for (const auto& [name, where] : medium_refs_)
    if (!is_predefined(name) && !desc_.media.contains(name))
      fail_at(where, fmt::format("unknown medium '{}'{}", name, suggestion(name, names)));
  if (!is_predefined(desc_.world_medium) && !desc_.media.contains(desc_.world_medium))
    fail_at("world_medium", fmt::format("unknown medium '{}'{}", desc_.world_medium, suggestion(desc_.world_medium, names)));
  return std::move(desc_);
}

}  // namespace bouguer
