#pragma once
// Path guiding for the path tracer (#37; the SD-tree is render/path_guide.h). Before the render,
// training iterations of the path tracer over the whole film, with 1, 2, 4, ... samples per pixel,
// each guided by what the iterations before it learned, each teaching the next (Müller et al.
// 2017's doubling schedule); their images are not kept. Every direction a training walk draws at a
// non-specular surface becomes a record: where, which way, and the light the walk then found that
// way (per unit of the throughput it left with, summed over the wavelengths) over the density that
// drew it. The render then draws half the directions at diffuse surfaces from the last
// iteration's trees and half from the BSDF, each weighted by f·cos over the mixture's density
// (one-sample MIS), so the estimate stays unbiased whatever the trees learned.
//
// The MIS weights between the walk and next-event estimation (lamps, the map, the connections
// through glass) read the BSDF's own density, not the mixture's: any function of the path serves
// if both sides read the same one (the weights still sum to 1, and the walk's density is never 0
// where the BSDF's is not), and this one leaves next-event estimation its share of the direct
// light. Weighted by the mixture, the guide, having learned where the lamps are, took weight from
// the connections through glass that do better there: the scattering ball of bench/guiding.sh
// came out 17 % noisier at equal samples (96×72).
//
// Scattering events are not guided. A guide that is not multiplied by the phase function draws
// directions whose weight phase/(α·p_guide + (1−α)·phase) runs from about 0.1 to 2 under a forward
// phase function, and over the hundreds of events of a dense walk those weights multiply into a
// tail no sample count reaches: the dense white furnace (g = 0.85, 550 events a path) read 0.07
// for 1 at 16 spp. The product with the phase function (Herholz et al. 2019), drawn by resampling,
// was measured on the whole-milk glass and taken back (docs/performance.md): its weights multiply
// over the walk too.
//
// Deterministic: an iteration's samples are seeded by (seed, iteration, pixel, sample) as the
// render's are, its records are added band by band of 16 rows, in pixel and sample order, to trees
// that change only between iterations; the training is the same whatever the render's threads,
// passes or processes (every rank of mpirun trains the same guide), so the guided image is too.
#include <cstdint>
#include <memory>

#include "bouguer/render/integrator.h"
#include "bouguer/render/path_guide.h"

namespace bouguer {

// Whether the settings' render is guided: the path tracer only (bdpt and vcm have their own
// strategies), where RenderSettings::guiding asks for it (off by default: on none of #37's scenes
// did it yet pay for its training at equal time, docs/performance.md).
bool guiding_enabled(const RenderSettings& settings);

struct GuideTraining {
  int iterations = 0;
  int spp = 0;  // samples per pixel the iterations took together
  std::uint64_t records = 0;
  double seconds = 0.0;
  std::size_t leaves = 0, bytes = 0;
};

// The guide for a render of `settings`: trained where guiding_enabled, null otherwise. The training
// takes as many doublings of the samples as fit in a quarter of the render's (1 + 2 + ... +
// 2^(k−1) ≤ spp/4), at least one, at most 7; fewer where `max_seconds` > 0 and the next would end
// past it, or where control.cancel is set. Its rays and seconds are added to stats; control.guide
// and control.active are not read.
std::unique_ptr<PathGuide> prepare_guide(const RenderScene& scene, const RenderSettings& settings,
                                         const RenderControl& control, RenderStats& stats, GuideTraining& report,
                                         double max_seconds = 0.0);

}  // namespace bouguer
