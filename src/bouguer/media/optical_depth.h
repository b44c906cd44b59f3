#pragma once
// One absorber's share of a segment's optical depth, as media hand it to the spectral tables
// (scene/spectral_tables.h): spectrum `id` times `length` (metres for a σ_a spectrum, or
// concentration × metres for an ε spectrum and a column density).
namespace bouguer {

struct OpticalDepthTerm {
  int id = -1;
  double length = 0.0;
};

}  // namespace bouguer
