#!/usr/bin/env bash
# Shell transport (#37, integrators/shell_hops.h) on and off for the path tracer, in one run of one
# build, alternating: the glass of whole milk (bench/scenes.py's `milk`), a 10 mm whole-milk ball
# under the same studio map, the glass again with a point lamp (`milk_lamp`: the spheres' kept
# collisions connect to it, and they keep clear of the glass by a margin) and with a sun
# (`milk_sun`). For each setting, PAIRS renders of two seeds each (seeds 1-2, 3-4, ...): the
# seconds of a render (its --stats-json, wall clock), the mean ΔE00 between the two seeds of a pair
# (about √2 times one render's error: noise only, which is all an exact change can move), and
# ΔE00² × seconds (lower is better; off / on is the efficiency gained). Reports only; figures in
# docs/performance.md.
#   bench/shell_transport.sh build/bouguer
# RESOLUTION (32x24), SPP (64), PAIRS (4), THREADS (2) and SCENES ("milk ball lamp sun") may be set.
set -euo pipefail
bin=$(realpath "$1")
resolution=${RESOLUTION:-32x24}
spp=${SPP:-64}
pairs=${PAIRS:-4}
threads=${THREADS:-2}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 "$repo/bench/scenes.py" "$tmp" milk milk_lamp milk_sun
mv "$tmp/milk_lamp.json" "$tmp/lamp.json"
mv "$tmp/milk_sun.json" "$tmp/sun.json"
# The ball: the milk scene's map and camera distance, its tumbler replaced by a 10 mm ball.
python3 - "$tmp" <<'PY'
import json, sys
d = json.load(open(sys.argv[1] + "/milk.json"))
d["objects"] = [{"name": "a 10 mm ball of whole milk", "shape": {"type": "sphere", "radius": "10 mm"},
                 "inside": "whole", "transform": [{"translate": [0, "45 mm", 0]}]}]
d["camera"]["fov_deg"] = 12
json.dump(d, open(sys.argv[1] + "/ball.json", "w"), indent=1)
PY
# shellcheck source=bench/seed_pairs.sh
source "$repo/bench/seed_pairs.sh"
echo "| scene | shell transport | seconds a render ($resolution, $spp spp, $threads threads) | mean ΔE00 seed to seed | ΔE00² × s |"
echo "|---|---|---|---|---|"
for scene in ${SCENES:-milk ball lamp sun}; do
  for setting in true false; do
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); d['render']['shell_transport']=sys.argv[2]=='true'; json.dump(d, open(sys.argv[3],'w'))" \
      "$tmp/$scene.json" "$setting" "$tmp/$scene-$setting.json"
  done
  declare -A secs=() gaps=()
  for pair in $(seq 1 "$pairs"); do
    for setting in true false; do  # alternating, so a busy machine slows both alike
      render_pair "$setting" "$bin" "$tmp/$scene-$setting.json" "$pair"
    done
  done
  pair_row "$scene" on true
  pair_row "$scene" off false
  unset secs gaps
done
