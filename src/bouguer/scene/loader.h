#pragma once
// Scene files (JSON, docs/scene-format.md) into a SceneDesc. Every error is one line naming the
// file and the key path ("scene.json: objects[2].shape.radius: ..."); unknown keys are errors
// with the nearest known key suggested.
#include <filesystem>
#include <string>

#include "bouguer/scene/description.h"

namespace bouguer {

SceneDesc load_scene(const std::filesystem::path& path);
SceneDesc parse_scene(const std::string& json_text, const std::filesystem::path& path);

// "5 mm", "0.5 cm", "1.2 um", "2 m" (or a plain number of metres) -> metres.
double parse_length_m(const std::string& text);

}  // namespace bouguer
