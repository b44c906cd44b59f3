#pragma once
// The front seam: every front end (the JSON loader, the glTF reader, the Python module) describes
// a scene through one SceneBuilder. Each part is checked where it is added — the physical checks
// live with the types they check — and its errors are one line naming the source and the place
// the front end gives (`where`, a Source: a file and a key path such as "objects[2]", or a
// command-line option); build() then checks what parts refer to (medium names) and returns the
// SceneDesc that compile accepts. Every file a scene names is read here or before, never in
// compile. Rewrites (spot lights with a radius become disks, the predefined media) happen in
// compile, not here.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "bouguer/scene/description.h"
#include "bouguer/scene/source.h"
#include "bouguer/scene/values.h"

namespace bouguer {

// The media every scene has without declaring them: "vacuum" (n = 1) and "air" (n = 1.000293).
const std::vector<MediumDesc>& predefined_media();

class SceneBuilder {
 public:
  explicit SceneBuilder(std::filesystem::path source);

  // A place in the builder's own source file, for front ends that read one file.
  Source at(std::string path) const { return {desc_.file, std::move(path)}; }

  SceneBuilder& camera(const CameraDesc& c, const Source& where);
  SceneBuilder& settings(const RenderSettings& s, const Source& where);
  SceneBuilder& world_medium(const std::string& name, const Source& where);
  SceneBuilder& medium(MediumDesc m, const Source& where);
  // A medium as a front end gives it (library names, units, RGB, files: scene/values.h).
  SceneBuilder& medium(const std::string& name, const MediumInput& m, const Source& where);
  SceneBuilder& object(ObjectDesc o, const Source& where);
  SceneBuilder& light(const DeltaLightDesc& l, const Source& where);
  SceneBuilder& background(const EmissionDesc& e, const Source& where);
  // Reads the map (an .exr or .pfm file) now, so compile reads no file.
  SceneBuilder& environment(const EnvironmentDesc& e, const Source& where);

  // Single settings as a front end or the command line gives them (names, whole numbers of any
  // size), each checked as settings() checks it, with one message: a scene's values and the
  // command line's overrides (called after the scene, so they win) pass the same check.
  SceneBuilder& integrator(const std::string& name, const Source& where);
  SceneBuilder& spectral_mode(const std::string& name, const Source& where);
  SceneBuilder& spp(std::int64_t spp, const Source& where);
  SceneBuilder& max_depth(std::int64_t depth, const Source& where);
  SceneBuilder& merge_radius(double radius_m, const Source& where);  // vcm's first merging radius
  SceneBuilder& exit_guide(bool on);  // path: RenderSettings::exit_guide
  SceneBuilder& manifold(bool on);    // path: RenderSettings::manifold
  SceneBuilder& area_lamp_chains(bool on);  // path: RenderSettings::area_lamp_chains
  SceneBuilder& guiding(bool on);     // path: RenderSettings::guiding
  SceneBuilder& light_paths(bool on);  // path: RenderSettings::light_paths
  SceneBuilder& shell_transport(bool on);  // path: RenderSettings::shell_transport
  SceneBuilder& seed(std::int64_t seed, const Source& where);
  SceneBuilder& resolution(std::int64_t width_px, std::int64_t height_px, const Source& where);

  // A value the front end let through but changed (an asset's value clamped into what Bouguer
  // models): one line, "file: place: message", kept in SceneDesc::warnings. Never for a mistake in
  // a scene written by hand: that is an Error.
  SceneBuilder& warn(const Source& where, const std::string& message);
  // The display (io/display.h; defined in builder_display.cpp), checked the same way: exposure
  // compensation in EV (−32 to 32), an absolute camera exposure (turns the automatic one off),
  // automatic exposure on or off (on clears a camera exposure), white balance by name (an
  // illuminant of spectra/cie.h, "brightest_emitter" or "none"), the curve ("clip", "filmic"),
  // and whether EXR, PFM and the spectral EXR are exposed and balanced too.
  SceneBuilder& exposure_ev(double ev, const Source& where);
  SceneBuilder& camera_exposure(const CameraExposure& c, const Source& where);
  SceneBuilder& auto_exposure(bool on);
  SceneBuilder& white_balance(const std::string& name, const Source& where);
  SceneBuilder& display_curve(const std::string& name, const Source& where);
  SceneBuilder& expose_float_outputs(bool on);
  bool auto_exposure_on() const { return desc_.display.auto_exposure; }

  // The checked description; an Error naming the place of a medium name that does not exist.
  SceneDesc build() &&;

 private:
  void refer_to_medium(const std::string& name, const Source& where);

  SceneDesc desc_;
  std::vector<std::pair<std::string, Source>> medium_refs_;  // (name, where)
  // The triangles and bytes of the meshes objects hold in memory (glTF primitives, Python's and
  // Blender's arrays: each object its own copy), checked as they grow, before compile copies them.
  std::uint64_t held_triangles_ = 0, held_bytes_ = 0, memory_budget_ = 0;
};

}  // namespace bouguer
