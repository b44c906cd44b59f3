#!/usr/bin/env bash
# Time to mean ΔE00 < 1 in chromatic scattering media (#20), for one or more builds of bouguer.
# 1. The strongly chromatic white furnace of #20 (σ_s 900 -> 30 per m over 400-700 nm, g 0.7, a
#    20 mm ball of index 1.33 under a uniform D65 sky, 8x8 through its middle; path, full and
#    hero), against the sky alone (every pixel of a furnace is the background), from 64 spp.
# 2. A skimmed-milk ball (4 mm, under the grey sky of tests/data/whole_milk_ball, 16x16, full, path)
# against a long reference rendered by the first build with every path tracked at one wavelength
# (the milk's index made to vary by 1e-6, as tests/data/whole_milk_ball/make_reference.sh does).
# 3. The whole-milk ball of Scattering.WholeMilkBallMatchesItsReference (1.5 mm, 16x16, full,
#    path) against the reference kept in tests/data/whole_milk_ball (16384 spp, one wavelength a
#    path; its README says how it was made).
# Each build renders at doubling spp (seed 1) until its mean ΔE00 to the reference is below 1 or
# MAX_SPP is passed. Reports only; the figures are in docs/performance.md.
#   bench/chromatic_convergence.sh build/bouguer [/path/to/other/bouguer ...]
# REF_SPP (16384), MAX_SPP (8192), THREADS (1) may be set.
set -euo pipefail
ref_spp=${REF_SPP:-16384}
max_spp=${MAX_SPP:-8192}
threads=${THREADS:-1}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$repo/tests/data/whole_milk_ball" "$tmp" <<'PY'
import json, sys
data, out = sys.argv[1], sys.argv[2]
scene = json.load(open(data + "/scene.json"))
scene["media"]["milk"]["scattering"]["library"] = "skimmed_milk"
scene["objects"][0]["shape"]["radius"] = "4 mm"
scene["camera"]["fov_deg"] = 22
scene["background"]["environment"] = data + "/sky.pfm"
json.dump(scene, open(out + "/skim.json", "w"), indent=1)
scene["media"]["milk"]["ior"] = {"wavelength_nm": [360, 830], "value": [1.3324284, 1.3324294]}
json.dump(scene, open(out + "/reference.json", "w"), indent=1)
PY
cat > "$tmp/furnace.json" <<'JSON'
{"camera": {"position": [0, 0, 0.16], "look_at": [0, 0, 0], "fov_deg": 5, "resolution": [8, 8]},
 "render": {"integrator": "path", "max_depth": 1000}, "world_medium": "vacuum",
 "media": {"milky": {"ior": 1.33, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
           "value": [900, 30], "phase": {"type": "henyey_greenstein", "g": 0.7}}}},
 "objects": [{"name": "ball", "shape": {"type": "sphere", "radius": "20 mm"}, "inside": "milky"}],
 "background": {"spectrum": "D65", "scale": 1}}
JSON
python3 - "$tmp" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1] + "/furnace.json"))
scene["objects"] = []
json.dump(scene, open(sys.argv[1] + "/sky.json", "w"))
PY
seconds() { python3 -c "import json,sys; print('%.2f' % json.load(open(sys.argv[1]))['seconds'])" "$1"; }
# converge SCENE REFERENCE FIRST_SPP MODE BUILD...: one table row per render
converge() {
  local scene=$1 reference=$2 first=$3 mode=$4
  shift 4
  for bin in "$@"; do
    local spp=$first
    while [ "$spp" -le "$max_spp" ]; do
      "$bin" render "$scene" --spectral "$mode" --spp "$spp" --seed 1 --threads "$threads" --quiet -o "$tmp/r.exr" \
        --stats-json "$tmp/r.stats"
      de=$("$1" compare "$tmp/r.exr" "$reference" | sed -n 's/.*mean \([0-9.]*\).*/\1/p')
      echo "| $(basename "$scene" .json) | $mode | $bin | $spp | $(seconds "$tmp/r.stats") | $de |"
      if python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 1 else 1)" "$de"; then break; fi
      spp=$((spp * 2))
    done
  done
}
"$1" render "$tmp/sky.json" --spp 1 --quiet -o "$tmp/sky.exr"
echo "| scene | mode | build | spp | seconds | mean ΔE00 |"
echo "|---|---|---|---|---|---|"
converge "$tmp/furnace.json" "$tmp/sky.exr" 64 full "$@"
converge "$tmp/furnace.json" "$tmp/sky.exr" 64 hero "$@"
"$1" render "$tmp/reference.json" --spp "$ref_spp" --seed 1000 --threads "$threads" --quiet \
  -o "$tmp/reference.exr" --stats-json "$tmp/reference.stats"
echo "reference: $ref_spp spp in $(seconds "$tmp/reference.stats") s"
converge "$tmp/skim.json" "$tmp/reference.exr" 96 full "$@"
python3 - "$repo/tests/data/whole_milk_ball" "$tmp" <<'PY'
import json, sys
data, out = sys.argv[1], sys.argv[2]
scene = json.load(open(data + "/scene.json"))
scene["background"]["environment"] = data + "/sky.pfm"
json.dump(scene, open(out + "/whole.json", "w"), indent=1)
PY
converge "$tmp/whole.json" "$repo/tests/data/whole_milk_ball/reference.exr" 32 full "$@"
