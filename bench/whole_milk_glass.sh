#!/usr/bin/env bash
# Time to mean ΔE00 < 1 for a glass of whole milk (#20): the whole-milk tumbler of
# scenes/showcase/milk-and-juice.json alone on its sweep under the studio map, framed so that it
# fills most of the picture, rendered small (RESOLUTION, 32x24 by default: the issue's 240x180 has
# 56 times the pixels, so a render there takes 56 times as long at the same spp, with about the
# same noise per pixel) against a long reference of the same build (REF_SPP, 2048, seed 1000: about
# 11 minutes on 2 cores), at doubling spp from 16 (seed 1) until the mean ΔE00 is below 1 or
# MAX_SPP (256) is passed. Reports only; the figures are in docs/performance.md.
#   bench/whole_milk_glass.sh build/bouguer
# THREADS (2) may be set.
set -euo pipefail
bin=$(realpath "$1")
ref_spp=${REF_SPP:-2048}
max_spp=${MAX_SPP:-256}
threads=${THREADS:-2}
resolution=${RESOLUTION:-32x24}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 "$repo/bench/scenes.py" "$tmp" milk
seconds() { python3 -c "import json,sys; print('%.2f' % json.load(open(sys.argv[1]))['seconds'])" "$1"; }
"$bin" render "$tmp/milk.json" --resolution "$resolution" --spp "$ref_spp" --seed 1000 --threads "$threads" --quiet \
  -o "$tmp/reference.exr" --stats-json "$tmp/reference.stats"
echo "reference: $resolution, $ref_spp spp in $(seconds "$tmp/reference.stats") s"
echo "| spp | seconds at $resolution | mean ΔE00 |"
echo "|---|---|---|"
spp=16
while [ "$spp" -le "$max_spp" ]; do
  "$bin" render "$tmp/milk.json" --resolution "$resolution" --spp "$spp" --seed 1 --threads "$threads" --quiet \
    -o "$tmp/r.exr" --stats-json "$tmp/r.stats"
  de=$("$bin" compare "$tmp/r.exr" "$tmp/reference.exr" | sed -n 's/.*mean \([0-9.]*\).*/\1/p')
  echo "| $spp | $(seconds "$tmp/r.stats") | $de |"
  if python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 1 else 1)" "$de"; then break; fi
  spp=$((spp * 2))
done
