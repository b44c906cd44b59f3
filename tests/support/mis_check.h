#pragma once
// The bidirectional estimators' MIS checked on the subpaths of one camera sample (the tests of
// bdpt's and vcm's weights): for every full path a strategy makes, the weights of all the
// strategies that could have made it, their densities recomputed from the geometry, summed (each
// sum must be 1), and the largest difference between the weight the renderer gave the strategy
// and the recomputed one. Connections to the lens (t = 1) are checked through media too: their
// scattering depth comes from the same transmission() the renderer's connection uses.
#include <cstddef>
#include <vector>

#include "bouguer/integrators/integrators.h"

namespace bouguer {

struct BdptMisCheck {
  std::vector<double> sums;
  double max_weight_difference = 0.0;
  std::size_t lens_through_media = 0;  // paths whose lens connection (t = 1) has a scattering depth > 0
  // vcm: full paths a merge makes (the light subpath to a photon, the camera subpath from the vertex
  // merged before it), and of them those no connection can make (every connection meets a
  // specular vertex: light scattered once in a liquid behind glass from a point lamp).
  std::size_t merge_paths = 0, merge_only_paths = 0;
};

// bdpt's strategies (bdpt.cpp) for camera sample `sample` of pixel (x, y).
BdptMisCheck bdpt_mis_check(const RenderScene& scene, const RenderSettings& settings, int x, int y, int sample);
// The same for vertex connection and merging (vcm.cpp): the merging strategies at every vertex
// where a path can merge are in each sum too (the radius of iteration `sample`), and the full
// paths merges make are checked besides those connections make.
BdptMisCheck vcm_mis_check(const RenderScene& scene, const RenderSettings& settings, int x, int y, int sample);

}  // namespace bouguer
