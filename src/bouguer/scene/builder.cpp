#include "bouguer/scene/builder.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/core/limits.h"
#include "bouguer/core/memory.h"
#include "bouguer/scene/nested.h"
#include "bouguer/media/medium.h"
#include "bouguer/scene/render_modes.h"

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

// Each setting's range, checked in one place for every front end and the command line.
constexpr std::int64_t kMaxSide = 16384, kMaxSpp = std::int64_t{1} << 20, kMaxDepth = 1000, kMaxSeed = 2147483647;

int count_between(std::int64_t v, std::int64_t lo, std::int64_t hi, const Source& where) {
  if (v < lo || v > hi) where.fail("must be between {} and {} (got {})", lo, hi, v);
  return static_cast<int>(v);
}

void check_resolution(std::int64_t w, std::int64_t h, const Source& where) {
  if (w < 1 || h < 1 || w > kMaxSide || h > kMaxSide)
    where.fail("each side must be 1 to {} pixels (got {}x{})", kMaxSide, w, h);
}

}  // namespace

SceneBuilder::SceneBuilder(std::filesystem::path source) { desc_.file = std::move(source); }

void SceneBuilder::refer_to_medium(const std::string& name, const Source& where) { medium_refs_.emplace_back(name, where); }

SceneBuilder& SceneBuilder::camera(const CameraDesc& c, const Source& where) {
  if (c.type == CameraType::pinhole && !(c.fov_deg > 0.0 && c.fov_deg < 180.0))
    (where / "fov_deg").fail("must be between 0 and 180 degrees");
  if (c.type == CameraType::orthographic && !(c.width_m > 0.0)) (where / "width").fail("must be a positive length");
  // Beyond a hundred image sides the window sees nothing the lens would: a mistake to point at.
  for (const auto& [i, s] : {std::pair{0, c.shift_x}, std::pair{1, c.shift_y}})
    if (!(std::abs(s) <= 100.0)) (where / "shift")[static_cast<std::size_t>(i)].fail("must be between -100 and 100 image sides (got {})", s);
  check_resolution(c.width_px, c.height_px, where / "resolution");
  auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(c.position_m)) (where / "position").fail("must be finite");
  if (!finite(c.look_at_m)) (where / "look_at").fail("must be finite");
  if (!(std::isfinite(length(c.up)) && length(c.up) > 0.0))
    (where / "up").fail("must be a direction of finite, non-zero length");
  const Vec3 forward = c.look_at_m - c.position_m;
  if (!(length(forward) > 0.0)) where.fail("'position' and 'look_at' coincide");
  if (!std::isfinite(length(forward))) where.fail("'position' and 'look_at' are too far apart");
  if (length(cross(normalize(forward), normalize(c.up))) < 1e-9)
    (where / "up").fail("'up' must not be parallel to the view direction");
  desc_.camera = c;
  return *this;
}

SceneBuilder& SceneBuilder::settings(const RenderSettings& s, const Source& where) {
  count_between(s.spp, 1, kMaxSpp, where / "spp");
  count_between(s.max_depth, 1, kMaxDepth, where / "max_depth");
  desc_.render = s;
  return *this;
}

SceneBuilder& SceneBuilder::integrator(const std::string& name, const Source& where) {
  const IntegratorInfo* info = find_integrator(name);
  if (!info) where.fail("unknown integrator '{}' ({})", name, integrator_names());
  desc_.render.integrator = info->type;
  return *this;
}

SceneBuilder& SceneBuilder::spectral_mode(const std::string& name, const Source& where) {
  const SpectralModeInfo* info = find_spectral_mode(name);
  if (!info) where.fail("unknown spectral mode '{}' ({})", name, spectral_mode_names());
  desc_.render.spectral = info->mode;
  return *this;
}

SceneBuilder& SceneBuilder::spp(std::int64_t v, const Source& where) {
  desc_.render.spp = count_between(v, 1, kMaxSpp, where);
  return *this;
}

SceneBuilder& SceneBuilder::max_depth(std::int64_t v, const Source& where) {
  desc_.render.max_depth = count_between(v, 1, kMaxDepth, where);
  return *this;
}

SceneBuilder& SceneBuilder::merge_radius(double radius_m, const Source& where) {
  if (!(radius_m > 0.0) || !std::isfinite(radius_m)) where.fail("the merging radius must be a positive length");
  desc_.render.merge_radius_m = radius_m;
  return *this;
}

SceneBuilder& SceneBuilder::exit_guide(bool on) {
  desc_.render.exit_guide = on;
  return *this;
}

SceneBuilder& SceneBuilder::area_lamp_chains(bool on) {
  desc_.render.area_lamp_chains = on;
  return *this;
}

SceneBuilder& SceneBuilder::manifold(bool on) {
  desc_.render.manifold = on;
  return *this;
}

SceneBuilder& SceneBuilder::light_paths(bool on) {
  desc_.render.light_paths = on;
  return *this;
}

SceneBuilder& SceneBuilder::shell_transport(bool on) {
  desc_.render.shell_transport = on;
  return *this;
}

SceneBuilder& SceneBuilder::guiding(bool on) {
  desc_.render.guiding = on;
  return *this;
}

SceneBuilder& SceneBuilder::seed(std::int64_t v, const Source& where) {
  desc_.render.seed = static_cast<std::uint64_t>(count_between(v, 0, kMaxSeed, where));
  return *this;
}

SceneBuilder& SceneBuilder::resolution(std::int64_t width_px, std::int64_t height_px, const Source& where) {
  check_resolution(width_px, height_px, where);
  desc_.camera.width_px = static_cast<int>(width_px);
  desc_.camera.height_px = static_cast<int>(height_px);
  return *this;
}

SceneBuilder& SceneBuilder::world_medium(const std::string& name, const Source& where) {
  desc_.world_medium = name;
  refer_to_medium(name, where);
  return *this;
}

SceneBuilder& SceneBuilder::medium(MediumDesc m, const Source& where) {
  if (is_predefined(m.name)) where.fail("'{}' is predefined; choose another name", m.name);
  if (desc_.media.contains(m.name)) where.fail("a medium named '{}' exists already", m.name);
  if (const auto problem = beyond_limit(m.sigma_a_per_m, kMaxCoefficientPerM, "the absorption coefficient σ_a (per metre)"))
    (where / "absorption").fail("{}", *problem);
  if (m.field_absorbers.size() > kMaxAbsorbersPerMedium)
    (where / "absorption").fail("at most {} absorbers per medium (got {})", kMaxAbsorbersPerMedium, m.field_absorbers.size());
  // The scatterers' own absorption is one more absorber of the compiled medium (compile.cpp).
  const std::size_t absorbers = std::max<std::size_t>(m.field_absorbers.size(), m.absorbing ? 1 : 0) +
                                (m.scattering && m.scattering->sigma_a_per_m ? 1 : 0);
  if (absorbers > kMaxAbsorbersPerMedium)
    (where / "absorption").fail("at most {} absorbers in a medium, its scatterers' own included", kMaxAbsorbersPerMedium);
  const bool density_scales_absorption = m.scattering && m.scattering->density && m.scattering->density_scales_absorption;
  for (std::size_t i = 0; i < m.field_absorbers.size(); ++i) {
    const FieldAbsorberDesc& a = m.field_absorbers[i];
    const Source at = m.field_absorbers.size() > 1 ? (where / "absorption")[i] : where / "absorption";
    if (const auto problem = beyond_limit(a.epsilon_per_m, kMaxCoefficientPerM, "σ_a per unit concentration"))
      at.fail("{}", *problem);
    if (min_value(a.epsilon_per_m) < 0.0) at.fail("σ_a must not be negative");
    check_concentration_field(a.field, at / "concentration");
    // A linear field grows without bound; its column densities are capped (concentration_field.h).
    const double peak = max_concentration(a.field);
    if (std::isfinite(peak) && !(peak * max_value(a.epsilon_per_m) <= kMaxCoefficientPerM))
      (at / "concentration")
          .fail("σ_a at the field's largest concentration ({:g}) exceeds {:g} per metre", peak, kMaxCoefficientPerM);
    if (density_scales_absorption && !std::holds_alternative<ConstantField>(a.field))
      at.fail("with a scattering 'density', the absorption's concentration must be a number (the density field scales it)");
  }
  if (m.scattering) {
    const Source at = where / "scattering";
    if (const auto problem = beyond_limit(m.scattering->sigma_s_per_m, kMaxCoefficientPerM, "the scattering coefficient σ_s (per metre)"))
      at.fail("{}", *problem);
    if (min_value(m.scattering->sigma_s_per_m) < 0.0) at.fail("σ_s must not be negative");
    if (m.scattering->sigma_a_per_m && min_value(*m.scattering->sigma_a_per_m) < 0.0)
      at.fail("the scatterers' σ_a must not be negative");
    if (const auto* hg = std::get_if<HenyeyGreensteinPhase>(&m.scattering->phase); hg && !(std::abs(hg->g) < 1.0))
      (at / "phase" / "g").fail("must lie strictly between −1 and 1 (got {})", hg->g);
    if (m.scattering->density) {
      // A library medium's `concentration` (its particles in another liquid) or a `density`.
      check_concentration_field(*m.scattering->density,
                                at / (m.scattering->density_scales_absorption ? "density" : "concentration"));
      const double peak = max_concentration(*m.scattering->density);
      const double sigma = std::max(max_value(m.scattering->sigma_s_per_m), max_value(m.sigma_a_per_m));
      if (std::isfinite(peak) && !(peak * sigma <= kMaxCoefficientPerM))
        (at / "density").fail("σ at the density's largest value ({:g}) exceeds {:g} per metre", peak, kMaxCoefficientPerM);
    }
  }
  const std::string name = m.name;
  desc_.media[name] = std::move(m);
  return *this;
}

SceneBuilder& SceneBuilder::medium(const std::string& name, const MediumInput& m, const Source& where) {
  return medium(resolve_medium(name, m, where), where);
}

namespace {

void check_roughness(double alpha, const Source& where) {
  if (!(alpha >= 0.0 && alpha <= 1.0)) where.fail("a GGX roughness (alpha) must be between 0 and 1 (got {})", alpha);
}

void check_material(const MaterialDesc& material, const Source& where) {
  if (const auto* d = std::get_if<DiffuseDesc>(&material)) {
    if (max_value(d->reflectance) > 1.0 || min_value(d->reflectance) < 0.0)
      (where / "reflectance").fail("a reflectance must lie between 0 and 1");
    return;
  }
  if (const auto* t = std::get_if<ThinDielectricDesc>(&material)) {
    if (!(t->ior >= 1.0 && t->ior < 5.0)) (where / "ior").fail("a refractive index must be between 1 and 5 (got {})", t->ior);
    if (max_value(t->tint) > 1.0 || min_value(t->tint) < 0.0) (where / "tint").fail("a tint must lie between 0 and 1");
    return;
  }
  if (const auto* g = std::get_if<MetallicRoughnessDesc>(&material)) {
    if (!(g->metalness >= 0.0 && g->metalness <= 1.0)) (where / "metalness").fail("must be between 0 and 1 (got {})", g->metalness);
    if (!(g->roughness >= 0.0 && g->roughness <= 1.0)) (where / "roughness").fail("must be between 0 and 1 (got {})", g->roughness);
    return;
  }
  const auto& c = std::get<ConductorDesc>(material);
  if (min_value(c.n) <= 0.0) (where / "n").fail("must be positive");
  if (min_value(c.k) < 0.0) (where / "k").fail("must not be negative");
  check_roughness(c.roughness, where / "roughness");
}

}  // namespace

namespace {

std::uint64_t mesh_bytes(const Mesh& m) {
  return m.positions.size() * sizeof(Vec3) + m.triangles.size() * sizeof(m.triangles[0]) +
         m.normals.size() * sizeof(Vec3) + m.uvs.size() * sizeof(m.uvs[0]) + m.tangents.size() * sizeof(Tangent);
}

}  // namespace

SceneBuilder& SceneBuilder::object(ObjectDesc o, const Source& where) {
  if (const auto* held = std::get_if<TriangleMeshShape>(&o.shape)) {
    // A thousand instances of a large mesh are a thousand copies: refused as they add up, not
    // when compile runs out of memory (a Blender render runs in Blender's own process).
    held_triangles_ += held->mesh.triangles.size();
    held_bytes_ += mesh_bytes(held->mesh);
    if (held_triangles_ > kMaxSceneTriangles)
      where.fail("the scene's meshes hold {} triangles so far, more than the limit of {}", held_triangles_,
                 kMaxSceneTriangles);
    if (memory_budget_ == 0) memory_budget_ = memory_available_bytes();
    // Twice what the copies hold: compile's scene takes as much again.
    require_memory(2 * held_bytes_, fmt::format("{}: {}: the scene's meshes so far", where.file.string(), where.path),
                   memory_budget_);
  }
  const int roles = int(o.inside.has_value()) + int(o.emission.has_value()) + int(o.material.has_value());
  if (roles != 1) where.fail("give exactly one of 'inside' (a medium interface), 'emission' or 'material'");
  if (!o.inside && (o.outside || o.contents || o.roughness != 0.0))
    where.fail("'outside', 'contents' and 'roughness' belong to interfaces ('inside')");
  check_roughness(o.roughness, where / "roughness");
  const double det = o.transform.determinant();
  if (!std::isfinite(det) || !std::isfinite(length(o.transform.translation)))
    (where / "transform").fail("the transform is not finite");
  if (det == 0.0) (where / "transform").fail("the transform is singular (it collapses the shape)");
  const bool vessel = std::holds_alternative<VesselShape>(o.shape);
  if (vessel && o.inside && !o.contents && std::get<VesselShape>(o.shape).fill > 0.0)
    where.fail("a filled vessel needs 'contents' (the liquid's medium)");
  if (!vessel && o.contents) (where / "contents").fail("only a vessel has contents");
  if (o.priority) {
    if (!o.inside) (where / "priority").fail("belongs to interfaces ('inside')");
    if (o.contents) (where / "priority").fail("a vessel with contents cannot take a priority: model the liquid as an object of its own");
    if (o.roughness != 0.0) (where / "priority").fail("only smooth interfaces take a priority (roughness 0)");
    if (*o.priority < 0 || *o.priority > kMaxPriority)
      (where / "priority").fail("must be between 0 and {} (got {})", kMaxPriority, *o.priority);
  }
  if (o.emission)
    if (const auto problem = beyond_limit(o.emission->radiance, kMaxEmission, "the emitted radiance"))
      (where / "emission").fail("{}", *problem);
  if (o.material) check_material(*o.material, where / "material");
  if (o.inside) refer_to_medium(*o.inside, where / "inside");
  if (o.outside) refer_to_medium(*o.outside, where / "outside");
  if (o.contents) refer_to_medium(*o.contents, where / "contents");
  desc_.objects.push_back(std::move(o));
  return *this;
}

SceneBuilder& SceneBuilder::light(const DeltaLightDesc& l, const Source& where) {
  if (l.type != DeltaLightType::point && std::abs(length(l.direction) - 1.0) > 1e-9)
    where.fail("the light's direction must be a unit vector");
  if (l.type == DeltaLightType::spot) {
    if (!(l.cone_deg > 0.0 && l.cone_deg <= 90.0)) (where / "cone_deg").fail("must be between 0 and 90 degrees");
    if (!(l.falloff_deg >= 0.0 && l.falloff_deg <= l.cone_deg))
      (where / "falloff_deg").fail("must be between 0 and cone_deg");
  }
  if (l.radius_m != 0.0 && l.type != DeltaLightType::spot) (where / "radius").fail("only a spot light takes a radius");
  if (!(l.radius_m >= 0.0)) (where / "radius").fail("must be a positive length");
  if (const auto problem = beyond_limit(l.intensity, kMaxEmission, "the light's intensity")) where.fail("{}", *problem);
  desc_.lights.push_back(l);
  return *this;
}

SceneBuilder& SceneBuilder::background(const EmissionDesc& e, const Source& where) {
  if (const auto problem = beyond_limit(e.radiance, kMaxEmission, "the background's radiance")) where.fail("{}", *problem);
  desc_.background = e;
  desc_.environment.reset();
  desc_.environment_map.reset();
  return *this;
}

SceneBuilder& SceneBuilder::environment(const EnvironmentDesc& e, const Source& where) {
  const Source file = where / "environment";
  const std::string ext = e.file.extension().string();
  if (ext != ".exr" && ext != ".pfm") file.fail("an environment map must be an .exr or .pfm file");
  if (!std::filesystem::exists(e.file)) file.fail("no such file: {}", e.file.string());
  if (!(e.scale >= 0.0 && e.scale <= kMaxEnvironmentRadiance))
    (where / "scale").fail("must be between 0 and {:g} (got {})", kMaxEnvironmentRadiance, e.scale);
  try {
    desc_.environment_map = std::make_shared<const EnvironmentMap>(load_environment(e));
  } catch (const Error& error) {
    file.fail("{}", error.what());
  }
  desc_.environment = e;
  return *this;
}

SceneBuilder& SceneBuilder::warn(const Source& where, const std::string& message) {
  desc_.warnings.push_back(fmt::format("{}: {}", where.name(), message));
  return *this;
}

SceneDesc SceneBuilder::build() && {
  std::vector<std::string> names;
  for (const MediumDesc& m : predefined_media()) names.push_back(m.name);
  for (const auto& [name, m] : desc_.media) names.push_back(name);
  for (const auto& [name, where] : medium_refs_)
    if (!is_predefined(name) && !desc_.media.contains(name))
      where.fail("unknown medium '{}'{}", name, suggestion(name, names));
  if (!is_predefined(desc_.world_medium) && !desc_.media.contains(desc_.world_medium))
    at("world_medium").fail("unknown medium '{}'{}", desc_.world_medium, suggestion(desc_.world_medium, names));
  if (const auto world = desc_.media.find(desc_.world_medium); world != desc_.media.end() && world->second.scattering)
    at("world_medium").fail("'{}' scatters; the world medium cannot (an unbounded scattering medium has no end to track "
                            "to): put the scattering medium inside an object",
                            desc_.world_medium);
  return std::move(desc_);
}

}  // namespace bouguer
