#!/usr/bin/env bash
# Every estimator on a dense medium (#20): the whole-milk ball of
# Scattering.WholeMilkBallMatchesItsReference (1.5 mm, 16x16, full, about a thousand scattering
# events a path) rendered by path, bdpt, vcm and bdpt with max_depth 8, at SPP (128, seed 1), for
# one or more builds; each row: seconds, mean ΔE00 and RMSE (linear RGB) against the reference kept
# in tests/data/whole_milk_ball (16384 spp, one wavelength a path; its image mean in linear RGB is
# 0.295 / 0.294 / 0.285), and the render's own image mean. Before the camera subpaths' tails
# (docs/rendering.md, "Depth, and dense media") bdpt and vcm came out about 25 % dark here.
# Reports only; the figures are in docs/performance.md.
#   bench/dense_estimators.sh build/bouguer [/path/to/other/bouguer ...]
# SPP (128), THREADS (2) may be set.
set -euo pipefail
spp=${SPP:-128}
threads=${THREADS:-2}
repo=$(cd "$(dirname "$0")/.." && pwd)
data="$repo/tests/data/whole_milk_ball"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
image_mean() {
  python3 - "$1" <<'PY'
import struct, sys
with open(sys.argv[1], "rb") as f:
    f.readline()
    w, h = (int(v) for v in f.readline().split())
    scale = float(f.readline())
    values = struct.unpack(("<" if scale < 0 else ">") + "f" * (w * h * 3), f.read(w * h * 12))
print(" / ".join("%.3f" % (sum(values[c::3]) / (w * h)) for c in range(3)))
PY
}
echo "| build | estimator | seconds | mean ΔE00 | RMSE | image mean |"
echo "|---|---|---|---|---|---|"
for bin in "$@"; do
  bin=$(realpath "$bin")
  for run in "path" "bdpt" "vcm" "bdpt 8"; do
    read -r integrator depth <<<"$run"
    args=(--integrator "$integrator" --spp "$spp" --seed 1 --threads "$threads" --quiet)
    [[ -n "${depth:-}" ]] && args+=(--max-depth "$depth")
    "$bin" render "$data/scene.json" "${args[@]}" -o "$tmp/out.pfm" --stats-json "$tmp/out.stats"
    seconds=$(python3 -c "import json,sys; print('%.2f' % json.load(open(sys.argv[1]))['seconds'])" "$tmp/out.stats")
    read -r de rmse < <("$bin" compare "$tmp/out.pfm" "$data/reference.exr" --json |
      python3 -c "import json,sys; d=json.load(sys.stdin); print('%.2f %.4f' % (d['mean'], d['rmse']))")
    label=$integrator
    [[ -n "${depth:-}" ]] && label="$integrator, max_depth $depth"
    echo "| $bin | $label | $seconds | $de | $rmse | $(image_mean "$tmp/out.pfm") |"
  done
done
