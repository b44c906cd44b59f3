#pragma once
// The Python module's scene: the description it was loaded from and the compiled scene it renders.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <memory>

#include "bouguer/scene/compile.h"
#include "bouguer/scene/description.h"

namespace bouguer::python {

// The last render's statistics (Scene.stats), updated after every pass while it runs.
struct RenderReport {
  double seconds = 0.0;
  std::uint64_t rays = 0;
  int spp_done = 0, spp_requested = 0;  // samples every pixel has; those asked for
  bool stopped = false;                 // should_stop() ended it
  std::string integrator;               // the estimator that rendered (auto: the one chosen)
};

struct Scene {
  SceneDesc desc;
  std::unique_ptr<RenderScene> compiled;
  RenderReport stats;
};

// The colour and materials tools (python/tools.cpp).
void register_tools(pybind11::module_& m);

}  // namespace bouguer::python
