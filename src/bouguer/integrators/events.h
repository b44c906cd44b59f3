#pragma once
// The events of a path, one function each, shared by every estimator that meets them (Whitted,
// the path tracer, the light tracer, bdpt, vcm), in files by concern; this header includes them
// all:
//   scene_view.h        what every event reads (SceneView) and the walks' limits
//   media_travel.h      a segment through media, escapes and emitters, Russian roulette
//   surface_assembly.h  a hit as a BSDF in its shading frame (SurfaceEvent, surface_event)
//   surface_events.h    what a path does at a surface: nested media, index-matched crossings,
//                       dispersion, the continuation
//   direct_light.h      connections (transmission) and next-event estimation, their MIS arithmetic
//   dense_media.h       the path tracer's dense-medium heuristics: thinning and splitting
//   exit_guide.h        the path tracer's next-event estimation through smooth interfaces
//   splats.h            the light tracer's connections to the camera
// A path owns its state (wavelengths, throughput, medium); these functions only read the scene.
#include "bouguer/integrators/dense_media.h"
#include "bouguer/integrators/direct_light.h"
#include "bouguer/integrators/exit_guide.h"
#include "bouguer/integrators/media_travel.h"
#include "bouguer/integrators/scene_view.h"
#include "bouguer/integrators/splats.h"
#include "bouguer/integrators/surface_assembly.h"
#include "bouguer/integrators/surface_events.h"
