#pragma once
// Scene files (JSON, docs/scene-format.md) into a SceneDesc, through the SceneBuilder. The loader
// reads JSON and nothing else: the structure (keys, types, which form a value takes), read into
// the builder's plain inputs (scene/values.h); what the values mean and every check of them are
// the builder's. Every error is one line naming the file and the key path
// ("scene.json: objects[2].shape.radius: ..."); unknown keys are errors with the nearest known
// key suggested.
#include <filesystem>
#include <map>
#include <string>

#include "bouguer/scene/builder.h"
#include "bouguer/scene/description.h"
#include "bouguer/scene/values.h"  // parse_length_m, for the callers that read lengths

namespace bouguer {

SceneDesc load_scene(const std::filesystem::path& path);
// Into a builder that the caller builds, after setting what overrides the file (the command line).
void load_scene(const std::filesystem::path& path, SceneBuilder& builder);
// Triangle meshes a front end holds in memory, by name, for shapes {"type": "mesh", "arrays": name}
// (Python's load_dict(meshes=...)); a scene file cannot name them.
using MeshArrays = std::map<std::string, TriangleMeshShape>;
SceneDesc parse_scene(const std::string& json_text, const std::filesystem::path& path,
                      const MeshArrays* arrays = nullptr);

}  // namespace bouguer
