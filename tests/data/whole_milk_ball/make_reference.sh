#!/usr/bin/env bash
# Renders reference.exr beside this script: the brute-force reference of the test
# Scattering.WholeMilkBallMatchesItsReference (tests/statistical/test_scattering.cpp), rendered
# once and committed. Usage, from the repository root after a Release build:
#   tests/data/whole_milk_ball/make_reference.sh [path/to/bouguer]   (SPP, SEED, THREADS may be set)
#
# What it renders: scene.json (a 1.5 mm ball of the library's whole_milk under sky.pfm, a grey
# sky brighter towards the zenith, 16x16, full) with one change: the milk's index varies by 1e-6
# over 360-830 nm (1.3324284 to 1.3324294) instead of being constant. That makes the ball's
# surface dispersive, so every path keeps one wavelength where it first meets the ball
# (keep_one_wavelength, integrators/events.h; in full mode the kept bin is stratified over the
# pixel's samples and the wavelength drawn within it) and is tracked at that wavelength alone
# from there on: analog delta tracking with that wavelength's own majorant, no spectral MIS
# (walk_factor is all ones once one wavelength is left, and the ratios r_u, r_l stay 1). It is
# independent of the spectral-MIS ratios that the test checks. The index change moves Fresnel
# reflectance and refraction angles by about 1e-6, far below the noise.
set -euo pipefail
bouguer=${1:-build/bouguer}
spp=${SPP:-16384}
seed=${SEED:-1000}
threads=${THREADS:-2}
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$here/scene.json" "$tmp/reference.json" "$here/sky.pfm" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["media"]["milk"]["ior"] = {"wavelength_nm": [360, 830], "value": [1.3324284, 1.3324294]}
scene["background"]["environment"] = sys.argv[3]
json.dump(scene, open(sys.argv[2], "w"), indent=2)
PY
echo "$bouguer render reference.json --spp $spp --seed $seed --threads $threads"
"$bouguer" render "$tmp/reference.json" --spp "$spp" --seed "$seed" --threads "$threads" --quiet \
  -o "$tmp/reference.exr" --stats-json "$tmp/stats.json"
cp "$tmp/reference.exr" "$here/reference.exr"
cat "$tmp/stats.json"; echo
