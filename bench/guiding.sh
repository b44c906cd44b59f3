#!/usr/bin/env bash
# Path guiding (#37, integrators/guiding.h) on and off for the path tracer, with and without its
# next-event estimation through glass, on bench/manifold.sh's two scenes (the scattering ball and
# the caustic under a red glass ball), measured as that script measures: seconds of one render
# (training included), the mean ΔE00 between seeds 1 and 2 over the frame and over the region that
# matters, and noise × √seconds (lower is better). Reports only; figures in docs/performance.md.
#   bench/guiding.sh build/bouguer
# SPP, RESOLUTION, THREADS and SCENES as for bench/manifold.sh.
set -euo pipefail
RUNS="path on off|path on on|path off off|path off on" exec "$(dirname "$0")/manifold.sh" "$@"
