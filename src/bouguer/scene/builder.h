#pragma once
// The front seam: every front end (the JSON loader today; glTF and Python later) describes a
// scene through one SceneBuilder. Each part is checked where it is added — the physical checks
// live with the types they check — and its errors are one line naming the source and the place
// the front end gives (`where`, a key path such as "objects[2]"); build() then checks what parts
// refer to (medium names) and returns the SceneDesc that compile accepts. Rewrites (spot lights
// with a radius become disks, the predefined media) happen in compile, not here.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "bouguer/scene/description.h"

namespace bouguer {

// The media every scene has without declaring them: "vacuum" (n = 1) and "air" (n = 1.000293).
const std::vector<MediumDesc>& predefined_media();

class SceneBuilder {
 public:
  explicit SceneBuilder(std::filesystem::path source);

  SceneBuilder& camera(const CameraDesc& c, const std::string& where = "camera");
  SceneBuilder& settings(const RenderSettings& s, const std::string& where = "render");
  SceneBuilder& world_medium(const std::string& name, const std::string& where = "world_medium");
  SceneBuilder& medium(MediumDesc m, const std::string& where);
  SceneBuilder& object(ObjectDesc o, const std::string& where);
  SceneBuilder& light(const DeltaLightDesc& l, const std::string& where);
  SceneBuilder& background(const EmissionDesc& e, const std::string& where = "background");
  SceneBuilder& environment(const EnvironmentDesc& e, const std::string& where = "background");

  // The checked description; an Error naming the place of a medium name that does not exist.
  SceneDesc build() &&;

 private:
  [[noreturn]] void fail_at(const std::string& where, const std::string& problem) const;
  void refer_to_medium(const std::string& name, const std::string& where);

  SceneDesc desc_;
  std::vector<std::pair<std::string, std::string>> medium_refs_;  // (name, where)
};

}  // namespace bouguer
