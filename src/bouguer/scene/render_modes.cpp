#include "bouguer/scene/render_modes.h"

#include "bouguer/core/error.h"

namespace bouguer {
namespace {

constexpr IntegratorInfo kIntegrators[] = {
    {IntegratorType::whitted, "whitted", "the paper's ray tracer: Fresnel-split interfaces, direct light by shadow rays",
     false, false, false},
    {IntegratorType::path, "path", "unbiased spectral path tracing with next-event estimation and MIS",
     true, false, true},
    {IntegratorType::light, "light",
     "light tracing: paths from the lamps connected to the camera (caustics on diffuse surfaces)", true,
     true, true},
    {IntegratorType::bdpt, "bdpt",
     "bidirectional path tracing: every connection of a camera and a light subpath, MIS (light through glass)",
     true, true, true},
    {IntegratorType::vcm, "vcm",
     "vertex connection and merging: bdpt and photon mapping under one MIS (caustics seen through glass)",
     true, true, true},
    // Its capabilities are the path tracer's, the one candidate for every scene; it may choose one
    // with splats (adaptive sampling makes it the path tracer).
    {IntegratorType::automatic, "auto",
     "short trials of path, bdpt and vcm choose the one with the least noise for its cost; the default of a scene "
     "that names none",
     true, false, true},
};

constexpr SpectralModeInfo kSpectralModes[] = {
    {SpectralMode::full, "full", "96 bins over 360-830 nm carried by every path"},
    {SpectralMode::hero, "hero", "4 wavelengths sampled per path (hero wavelength sampling)"},
    {SpectralMode::rgb3, "rgb3", "the paper's RGB: absorption at 700.0, 546.1 and 435.8 nm"},
};

template <typename Table>
std::string names_of(const Table& table) {
  std::string s;
  for (std::size_t i = 0; i < std::size(table); ++i)
    s += (i == 0 ? "" : i + 1 == std::size(table) ? " or " : ", ") + std::string(table[i].name);
  return s;
}

}  // namespace

std::span<const IntegratorInfo> integrator_table() { return kIntegrators; }

const IntegratorInfo* find_integrator(std::string_view name) {
  for (const IntegratorInfo& i : kIntegrators)
    if (i.name == name) return &i;
  return nullptr;
}

const IntegratorInfo& integrator_info(IntegratorType type) {
  for (const IntegratorInfo& i : kIntegrators)
    if (i.type == type) return i;
  fail("internal error: integrator {} has no table entry", static_cast<int>(type));
}

std::span<const SpectralModeInfo> spectral_mode_table() { return kSpectralModes; }

const SpectralModeInfo* find_spectral_mode(std::string_view name) {
  for (const SpectralModeInfo& m : kSpectralModes)
    if (m.name == name) return &m;
  return nullptr;
}

std::string_view spectral_mode_name(SpectralMode mode) {
  for (const SpectralModeInfo& m : kSpectralModes)
    if (m.mode == mode) return m.name;
  return "?";
}

std::string integrator_names() { return names_of(kIntegrators); }
std::string spectral_mode_names() { return names_of(kSpectralModes); }

}  // namespace bouguer
