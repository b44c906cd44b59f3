#!/usr/bin/env bash
# Next-event estimation from a walk in a dense medium (#37, dense_media.h: split_walk_nee_share),
# for one or more builds of bouguer, alternating in one run: the glass of whole milk of
# bench/scenes.py under its studio map alone (`milk`), with a point lamp (`milk_lamp`) and with a
# sun (`milk_sun`), whose light reaches the milk through the glass by solved refractions. For each
# build, PAIRS renders of two seeds each (seeds 1-2, 3-4, ...): the seconds of a render (its
# --stats-json, wall clock), the mean ΔE00 between the two seeds of a pair (about √2 times one
# render's error: noise only, which is all an exact change can move), and ΔE00² × seconds (lower
# is better: one build's over another's is the efficiency between them). Reports only; figures in
# docs/performance.md.
#   bench/dense_connections.sh build/bouguer [/path/to/other/bouguer ...]
# RESOLUTION (32x24), SPP (64), PAIRS (2), THREADS (2) and SCENES ("milk_sun milk_lamp milk") may be set.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: bench/dense_connections.sh BOUGUER [BOUGUER ...]" >&2; exit 2; }
bins=()
for b in "$@"; do bins+=("$(realpath "$b")"); done
resolution=${RESOLUTION:-32x24}
spp=${SPP:-64}
pairs=${PAIRS:-2}
threads=${THREADS:-2}
scenes=${SCENES:-milk_sun milk_lamp milk}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# shellcheck disable=SC2086
python3 "$repo/bench/scenes.py" "$tmp" $scenes
# shellcheck source=bench/seed_pairs.sh
source "$repo/bench/seed_pairs.sh"
echo "| scene | build | seconds a render ($resolution, $spp spp, $threads threads) | mean ΔE00 seed to seed | ΔE00² × s |"
echo "|---|---|---|---|---|"
for scene in $scenes; do
  declare -A secs=() gaps=()
  for pair in $(seq 1 "$pairs"); do
    for i in "${!bins[@]}"; do  # alternating, so a busy machine slows every build alike
      render_pair "$i" "${bins[$i]}" "$tmp/$scene.json" "$pair"
    done
  done
  for i in "${!bins[@]}"; do pair_row "$scene" "${bins[$i]}" "$i"; done
  unset secs gaps
done
