#!/usr/bin/env bash
# A red glass ball under a small spherical lamp (#37: the caustic and the coloured shadow under the
# ball are the point), the lamp exact (lights/light.h: SphereLight, sampled by the cone it
# subtends) against the same lamp tessellated ("tessellate": true: one area light per triangle,
# drawn by area, half of them facing away), for path, bdpt and vcm. Each row: seconds for two
# renders of seeds 1 and 2, their mean ΔE00 (the noise), and noise × √(seconds of one render):
# lower is better, and its ratio between two rows is the square root of their efficiency ratio.
# Reports only; the figures are in docs/performance.md.
#   bench/sphere_lamp.sh build/bouguer
# SPP (64), RESOLUTION (96x72), THREADS (2), RADIUS (5 mm) may be set.
set -euo pipefail
bin=${1:-build/bouguer}
spp=${SPP:-64}
resolution=${RESOLUTION:-96x72}
threads=${THREADS:-2}
radius=${RADIUS:-"5 mm"}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# tests/data/red_ball_lamp, its lamp as RADIUS says, tessellated or not.
scene() {  # scene TESSELLATE
  python3 - "$repo/tests/data/red_ball_lamp/scene.json" "$1" "$radius" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
for o in scene["objects"]:
    if o["name"] == "lamp":
        o["shape"]["tessellate"] = sys.argv[2] == "true"
        o["shape"]["radius"] = sys.argv[3]
        o["emission"]["scale"] = 2000
scene["render"]["max_depth"] = 16
scene.pop("background")
print(json.dumps(scene))
PY
}
scene false >"$tmp/exact.json"
scene true >"$tmp/tessellated.json"
echo "| lamp | estimator | spp | seconds (one render) | seed-to-seed mean ΔE00 | ΔE00 × √s |"
echo "|---|---|---|---|---|---|"
for lamp in exact tessellated; do
  for integrator in path bdpt vcm; do
    total=0
    for seed in 1 2; do
      "$bin" render "$tmp/$lamp.json" --integrator "$integrator" --spp "$spp" --resolution "$resolution" \
        --threads "$threads" --seed "$seed" -o "$tmp/$lamp-$integrator-$seed.exr" --stats-json "$tmp/s.json" --quiet
      s=$(tr -d '\n ' <"$tmp/s.json" | sed -E 's/.*"seconds":([0-9.e+-]+).*/\1/')
      total=$(echo "$total $s" | awk '{print $1 + $2}')
    done
    de=$("$bin" compare "$tmp/$lamp-$integrator-1.exr" "$tmp/$lamp-$integrator-2.exr" | sed -n 's/.*mean \([0-9.]*\).*/\1/p')
    echo "$lamp $integrator $spp $total $de" | awk '{s = $4 / 2; printf "| %s | %s | %s | %.2f | %s | %.3f |\n", $1, $2, $3, s, $5, $5 * sqrt(s)}'
  done
done
