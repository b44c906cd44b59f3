#pragma once
// The integrators and spectral modes by name: the only lists of them. The scene builder, the
// command line and the documentation read these; integrators/render_into.cpp binds each
// integrator to its render function (this layer is below the estimators).
#include <span>
#include <string>
#include <string_view>

#include "bouguer/scene/description.h"
#include "bouguer/spectra/sampled_wavelengths.h"

namespace bouguer {

struct IntegratorInfo {
  IntegratorType type;
  std::string_view name;
  std::string_view summary;
  bool rough_interfaces;  // whether it handles rough dielectric interfaces
  bool splats;            // whether its light arrives through the film's splat buffer
  bool scattering_media;  // whether it renders media that scatter
};

std::span<const IntegratorInfo> integrator_table();
const IntegratorInfo* find_integrator(std::string_view name);
const IntegratorInfo& integrator_info(IntegratorType type);

struct SpectralModeInfo {
  SpectralMode mode;
  std::string_view name;
  std::string_view summary;
};
std::span<const SpectralModeInfo> spectral_mode_table();
const SpectralModeInfo* find_spectral_mode(std::string_view name);
std::string_view spectral_mode_name(SpectralMode mode);

// "a, b or c": the names of a table, for messages and help texts.
std::string integrator_names();
std::string spectral_mode_names();

}  // namespace bouguer
