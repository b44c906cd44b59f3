#!/usr/bin/env bash
# Where the noise of the glass of whole milk comes from (#37): bench/scenes.py's `milk` (the
# whole-milk tumbler on its sweep under the studio map) rendered by pairs of seeds as it is and
# with one source of light or one strategy taken away at a time:
#   studio            as it is (the exit guide on: the map's contrast is 12)
#   studio, no guide  "exit_guide": false (the milk lit only by the walks' own exits)
#   flat map          the studio map replaced by a constant map of the same mean (guide off there)
#   flat map, guide   the same with "exit_guide": true
#   black sweep       the sweep's reflectance 0 (the milk lit by the map alone, not by the sweep)
#   ink in the glass  the milk replaced by an absorbing liquid (only the glass's reflections left)
# For each: the seconds of one render, the mean ΔE00 between the two seeds of a pair over the
# frame, ΔE00² × seconds, that mean from lightness alone and from colour alone (bouguer compare:
# per pixel the two add in quadrature), and in the milk's pixels (the middle of the glass) the mean
# luminance Y and the standard deviation of one sample's Y (from the pairs' differences), absolute
# and over Y.
# Reports only; the figures are in docs/performance.md ("Where the whole-milk glass's noise comes
# from").
#   bench/milk_noise.sh build/bouguer
# RESOLUTION (32x24), SPP (64), THREADS (2) and PAIRS (1) may be set.
set -euo pipefail
bin=$(realpath "$1")
resolution=${RESOLUTION:-32x24}
spp=${SPP:-64}
threads=${THREADS:-2}
pairs=${PAIRS:-1}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# shellcheck source=bench/seed_pairs.sh
source "$repo/bench/seed_pairs.sh"
declare -A secs gaps

python3 "$repo/bench/scenes.py" "$tmp" milk
python3 - "$tmp" <<'PY'
import copy, json, math, struct, sys
tmp = sys.argv[1]
base = json.load(open(f"{tmp}/milk.json"))

def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = f.read()
    fmt = ("<" if scale < 0 else ">") + "f" * (3 * w * h)
    return w, h, struct.unpack(fmt, data[: 12 * w * h])

# The studio map's mean radiance over the sphere (its texels weighted by sin θ), in RGB.
w, h, px = read_pfm(base["background"]["environment"])
scale = base["background"].get("scale", 1.0)
mean, weight = [0.0, 0.0, 0.0], 0.0
for j in range(h):
    s = math.sin(math.pi * (j + 0.5) / h)
    weight += s * w
    for i in range(w):
        t = 3 * (j * w + i)
        for c in range(3):
            mean[c] += s * px[t + c]
mean = [m / weight * scale for m in mean]
with open(f"{tmp}/flat.pfm", "wb") as f:
    f.write(b"PF\n8 4\n-1.0\n" + struct.pack("<" + "f" * 96, *(mean * 32)))

def variant(name, edit):
    scene = copy.deepcopy(base)
    edit(scene)
    json.dump(scene, open(f"{tmp}/{name}.json", "w"))

def render(scene, key, value):
    scene["render"][key] = value

def flat(scene, guide=None):
    scene["background"] = {"environment": f"{tmp}/flat.pfm", "scale": 1.0}
    if guide is not None:
        scene["render"]["exit_guide"] = guide

def sweep(scene):
    for o in scene["objects"]:
        if "sweep" in o["name"]:
            o["material"]["reflectance"] = 0.0

def ink(scene):
    scene["media"]["ink"] = {"ior": 1.35, "absorption": {"unit": "attenuation_per_m",
                                                         "wavelength_nm": [360, 830], "value": [1e5, 1e5]}}
    for o in scene["objects"]:
        if o.get("contents") == "whole":
            o["contents"] = "ink"

variant("studio", lambda s: None)
variant("noguide", lambda s: render(s, "exit_guide", False))
variant("flat", flat)
variant("flatguide", lambda s: flat(s, True))
variant("black", sweep)
variant("ink", ink)
PY

# The milk's pixels (columns 10/32 to 22/32, rows 3/24 to 24/24 of the frame: inside the glass's
# outline): their mean Y, one sample's σ(Y) and σ(Y)/Y, from TAG's pairs.
milk_noise() {
  python3 - "$tmp" "$1" "$pairs" "$spp" <<'PY'
import math, struct, sys
tmp, tag, pairs, spp = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
def y(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        v = struct.unpack(("<" if scale < 0 else ">") + "f" * (3 * w * h), f.read()[: 12 * w * h])
    # (PFM rows run from the bottom)
    return w, h, [[0.2126 * v[3 * ((h - 1 - j) * w + i)] + 0.7152 * v[3 * ((h - 1 - j) * w + i) + 1]
                   + 0.0722 * v[3 * ((h - 1 - j) * w + i) + 2] for i in range(w)] for j in range(h)]
mean, var, n = 0.0, 0.0, 0
for p in range(1, pairs + 1):
    w, h, a = y(f"{tmp}/r-{tag}-{2 * p - 1}.pfm")
    _, _, b = y(f"{tmp}/r-{tag}-{2 * p}.pfm")
    for j in range(h * 3 // 24, h):
        for i in range(w * 10 // 32, w * 22 // 32):
            mean += (a[j][i] + b[j][i]) / 2
            var += (a[j][i] - b[j][i]) ** 2 / 2 * spp  # (the variance of one render times spp)
            n += 1
mean /= n
sigma = math.sqrt(var / n)
print(f"{mean:.3f} | {sigma:.3f} | {sigma / mean:.2f}" if mean > 0 else "- | - | -")
PY
}

# The frame's mean ΔE00 between TAG's seeds from lightness alone and from colour alone, over its pairs.
parts() {
  for p in $(seq 1 "$pairs"); do "$bin" compare "$tmp/r-$1-$((2 * p - 1)).pfm" "$tmp/r-$1-$((2 * p)).pfm" --json; done |
    python3 -c "
import json, sys
d = [json.loads(line) for line in sys.stdin]
print(f\"{sum(x['mean_lightness'] for x in d) / len(d):.2f} | {sum(x['mean_colour'] for x in d) / len(d):.2f}\")"
}

echo "milk_noise: $resolution, $spp spp, $threads threads, $pairs pair(s) of seeds"
echo "| variant | seconds (range) | frame ΔE00 between seeds (each pair) | ΔE00² × s | of it, lightness alone | colour alone | milk: Y | one sample's σ(Y) | σ(Y)/Y |"
echo "|---|---|---|---|---|---|---|---|---|"
for tag in studio noguide flat flatguide black ink; do
  for pair in $(seq 1 "$pairs"); do render_pair "$tag" "$bin" "$tmp/$tag.json" "$pair"; done
  row=$(pair_row "$tag" "" "$tag" | sed 's/ |  | / | /')
  echo "${row% |} | $(parts "$tag") | $(milk_noise "$tag") |"
done
