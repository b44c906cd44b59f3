#pragma once
// The Python module's scene: the description it was loaded from and the compiled scene it renders.
#include <pybind11/pybind11.h>

#include <memory>

#include "bouguer/scene/compile.h"
#include "bouguer/scene/description.h"

namespace bouguer::python {

struct Scene {
  SceneDesc desc;
  std::unique_ptr<RenderScene> compiled;
};

// The colour and materials tools (python/tools.cpp).
void register_tools(pybind11::module_& m);

}  // namespace bouguer::python
