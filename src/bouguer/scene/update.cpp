#include "bouguer/scene/update.h"

#include <algorithm>
#include <cmath>
#include <variant>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/core/limits.h"
#include "bouguer/scene/builder.h"
#include "bouguer/spectra/cie.h"

namespace bouguer {
namespace {

SceneMedium& compiled_medium(RenderScene& scene, const std::string& name, const Source& where, const SceneDesc& desc) {
  for (SceneMedium& m : scene.media)
    if (m.name == name) return m;
  where.fail("no medium '{}' in the scene ({})", name, medium_names(desc));
}

// The absorption spectra of a compiled medium with the description's spectrum each came from,
// in the order compile lowered them (scene/compile.cpp: lower_medium, lower_scattering).
std::vector<std::pair<int, const Spectrum*>> absorption_spectra(const SceneMedium& m, const MediumDesc& d) {
  std::vector<std::pair<int, const Spectrum*>> out;
  if (const auto* h = std::get_if<HomogeneousMedium>(&m.medium)) {
    if (h->sigma_a >= 0) out.emplace_back(h->sigma_a, &d.sigma_a_per_m);
    return out;
  }
  const std::vector<FieldAbsorber>& absorbers = std::holds_alternative<FieldMedium>(m.medium)
                                                    ? std::get<FieldMedium>(m.medium).absorbers
                                                    : std::get<ScatteringMedium>(m.medium).absorbers;
  // A scattering medium with a uniform absorption lowers it as its first absorber, σ_a itself;
  // the absorbers after the medium's own are its scatterers' (not the medium's absorption).
  if (d.field_absorbers.empty()) {
    if (d.absorbing && !absorbers.empty()) out.emplace_back(absorbers.front().epsilon, &d.sigma_a_per_m);
    return out;
  }
  for (std::size_t i = 0; i < absorbers.size() && i < d.field_absorbers.size(); ++i)
    out.emplace_back(absorbers[i].epsilon, &d.field_absorbers[i].epsilon_per_m);
  return out;
}

}  // namespace

std::string medium_names(const SceneDesc& desc) {
  std::string names;
  for (const auto& [name, m] : desc.media) names += (names.empty() ? "" : ", ") + name;
  return names;
}

void set_absorption_scale(RenderScene& scene, const SceneDesc& desc, const std::string& name, double factor,
                          const Source& where) {
  const auto found = desc.media.find(name);
  if (found == desc.media.end()) where.fail("no medium '{}' in the scene ({})", name, medium_names(desc));
  if (!std::isfinite(factor) || factor < 0.0) where.fail("the absorption scale must be a finite number >= 0 (got {})", factor);
  SceneMedium& m = compiled_medium(scene, name, where, desc);
  const auto spectra = absorption_spectra(m, found->second);
  // Every spectrum is checked before any is changed: a failed update leaves the scene as it was.
  std::vector<Spectrum> updated;
  for (const auto& [id, source] : spectra) {
    updated.push_back(scaled(*source, factor));
    if (!(max_value(updated.back()) <= kMaxCoefficientPerM))
      where.fail("σ_a times {:g} exceeds {:g} per metre (docs/limits.md)", factor, kMaxCoefficientPerM);
  }
  for (std::size_t i = 0; i < spectra.size(); ++i)
    scene.spectra[static_cast<std::size_t>(spectra[i].first)].source = std::move(updated[i]);
}

void set_emission_scale(RenderScene& scene, const SceneDesc& desc, const std::string& object, double factor,
                        const Source& where) {
  if (!std::isfinite(factor) || factor < 0.0) where.fail("the emission scale must be a finite number >= 0 (got {})", factor);
  int spectrum = -1;
  const Spectrum* source = nullptr;
  if (object == "background") {
    if (scene.background_light < 0) where.fail("the scene's background is an environment map (its scale is not updated)");
    spectrum = std::get<BackgroundLight>(scene.lights[static_cast<std::size_t>(scene.background_light)]).radiance;
    source = &desc.background.radiance;
  } else {
    std::string emitters;
    for (const ObjectDesc& o : desc.objects)
      if (o.emission) emitters += (emitters.empty() ? "" : ", ") + o.name;
    const auto found = std::find_if(desc.objects.begin(), desc.objects.end(),
                                    [&](const ObjectDesc& o) { return o.name == object && o.emission; });
    if (found == desc.objects.end())
      where.fail("no emitter '{}' in the scene (emitters: {}; or \"background\")", object, emitters.empty() ? "none" : emitters);
    for (const Surface& s : scene.surfaces)
      if (s.kind == SurfaceKind::emitter && s.object == object && s.first_light >= 0) {
        spectrum = emitter_radiance(scene.lights[static_cast<std::size_t>(s.first_light)]).spectrum;
        break;
      }
    if (spectrum < 0) where.fail("the emitter '{}' has no area in the compiled scene", object);
    source = &found->emission->radiance;
  }
  Spectrum updated = scaled(*source, factor);
  if (!std::isfinite(max_value(updated))) where.fail("the emission times {:g} is not finite", factor);
  scene.spectra[static_cast<std::size_t>(spectrum)].source = std::move(updated);
  set_light_distributions(scene);
}

void set_light_distributions(RenderScene& s) {
  std::vector<double> luminance_of(s.spectra.size(), 0.0);
  for (std::size_t i = 0; i < s.spectra.size(); ++i)
    if (const auto* sp = std::get_if<Spectrum>(&s.spectra[i].source)) luminance_of[i] = luminance(*sp);
  std::vector<bool> area, delta, all(s.lights.size(), true);
  s.light_power.clear();
  for (const Light& l : s.lights) {
    s.light_power.push_back(power(l, s.bounds, [&](int id) { return id < 0 ? 0.0 : luminance_of[static_cast<std::size_t>(id)]; }));
    area.push_back(on_a_surface(l));
    delta.push_back(std::holds_alternative<PointLight>(l) || std::holds_alternative<SpotLight>(l) ||
                    std::holds_alternative<DistantLight>(l));
  }
  s.area_lights = LightDistribution::by_power(s.light_power, area);
  s.emitters = LightDistribution::by_power(s.light_power, all);
  s.delta_lamps = LightDistribution::by_power(s.light_power, delta);
}

void set_camera(RenderScene& scene, const SceneDesc& desc, const CameraDesc& camera, const Source& where) {
  SceneBuilder check(desc.file);
  check.camera(camera, where);
  scene.camera = camera;
}

}  // namespace bouguer
