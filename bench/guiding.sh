#!/usr/bin/env bash
# Path guiding (#37, integrators/guiding.h) on and off for the path tracer, with and without its
# next-event estimation through glass, on bench/manifold.sh's scenes (the scattering ball, the
# caustic under a red glass ball, and `bounce`: a floor lit only by a small white patch a lamp
# shines on, guiding's textbook case), measured as that script measures: seconds of one render
# (training included), the mean ΔE00 between seeds 1 and 2 over the frame and over the region that
# matters (bounce: the frame), and noise × √seconds (lower is better). At 384×288 by default: the
# guide learns from the training's records, and a 96×72 render has too few of them.
# Reports only; figures in docs/performance.md.
#   bench/guiding.sh build/bouguer
# SPP (64), RESOLUTION (384x288), THREADS (2) and SCENES ("ball caustic bounce") may be set.
set -euo pipefail
RUNS="path on off|path on on|path off off|path off on" RESOLUTION=${RESOLUTION:-384x288} \
  SCENES=${SCENES:-"ball caustic bounce"} exec "$(dirname "$0")/manifold.sh" "$@"
