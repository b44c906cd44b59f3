#pragma once
// The Python module's scene: the description it was loaded from and the compiled scene it renders.
#include <memory>

#include "bouguer/scene/compile.h"
#include "bouguer/scene/description.h"

namespace bouguer::python {

struct Scene {
  SceneDesc desc;
  std::unique_ptr<RenderScene> compiled;
};

}  // namespace bouguer::python
