#!/usr/bin/env bash
# Next-event estimation through smooth glass (#37, integrators/manifold.h), on and off
# ("manifold": false in the scene), for the path tracer, beside bdpt and vcm, on two of the
# issue's scenes:
#   ball     a ball of scattering medium inside a refracting boundary (n = 1.33, σ_s 30/12/6 per m
#            at 450/550/650 nm, g 0.7, radius 50 mm) on a grey floor under a 200 mm square lamp
#            (every scattering event inside reaches the lamp through one crossing)
#   caustic  tests/data/red_ball_lamp: a red glass ball under a 5 mm spherical lamp (the caustic
#            and the coloured shadow come through two crossings)
#   softbox  the lit tumbler under a 20 mm softbox and a 5 mm emitting sphere (bench/scenes.py): the
#            liquid's scattering events reach them through chains of the glass's mesh faces
# Each row: seconds of one render (seeds 1 and 2), their mean ΔE00 (the noise) over the whole
# frame and over the region the connections are for (ball: the ball, x 30–70 % and y 20–75 % of
# the frame from its top left; caustic: the shadow and the caustic beside the ball, x 42–64 %,
# y 56–66 %; softbox: the liquid, x 35–65 %, y 45–70 %), and noise × √seconds (lower is better;
# the ratio of two rows' is the square root of their efficiency ratio). Reports only; figures in docs/performance.md.
#   bench/manifold.sh build/bouguer
# SPP (64), RESOLUTION (96x72), THREADS (2), SCENES ("ball caustic"), RUNS may be set.
set -euo pipefail
bin=$(realpath "${1:-build/bouguer}")
spp=${SPP:-64}
resolution=${RESOLUTION:-96x72}
threads=${THREADS:-2}
scenes=${SCENES:-"ball caustic"}
# The estimators compared, '|'-separated: integrator, manifold on|off, guiding on|off (bench/guiding.sh
# sets its own).
runs=${RUNS:-"path on|path off|bdpt off|vcm off"}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$repo" "$tmp" <<'PY'
import json, os, sys
sys.path.insert(0, os.path.join(sys.argv[1], "bench"))
import scenes  # bench/scenes.py: ball, caustic, softbox and bounce
for name in ("ball", "caustic", "softbox", "bounce"):
    for manifold in (True, False):
        s = scenes.scene(name)
        s["render"]["manifold"] = manifold
        json.dump(s, open(os.path.join(sys.argv[2], "%s-%s.json" % (name, "on" if manifold else "off")), "w"))
PY
# Mean ΔE00 between two renders over the whole frame and over the region (x0 x1 y0 y1, fractions).
noise() {
  python3 - "$bin" "$1" "$2" "$tmp" "$3" <<'PY'
import json, subprocess, sys, struct
bin, a, b, tmp = sys.argv[1:5]
fx0, fx1, fy0, fy1 = (float(v) for v in sys.argv[5].split())
def mean_de(x, y):
    return json.loads(subprocess.run([bin, "compare", x, y, "--json"], check=True, capture_output=True,
                                     text=True).stdout)["mean"]
def crop(src, dst):  # (PFM rows run bottom to top)
    with open(src, "rb") as f:
        f.readline()
        w, h = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        end = "<" if scale < 0 else ">"
        values = struct.unpack(end + "f" * (w * h * 3), f.read(w * h * 12))
    x0, x1 = int(fx0 * w), int(fx1 * w)
    r0, r1 = h - int(fy1 * h), h - int(fy0 * h)
    out = [values[(y * w + x) * 3 + c] for y in range(r0, r1) for x in range(x0, x1) for c in range(3)]
    with open(dst, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (x1 - x0, r1 - r0))
        f.write(struct.pack("<" + "f" * len(out), *out))
crop(a, tmp + "/ca.pfm")
crop(b, tmp + "/cb.pfm")
print("%.3f %.3f" % (mean_de(a, b), mean_de(tmp + "/ca.pfm", tmp + "/cb.pfm")))
PY
}
echo "| scene | estimator | spp | seconds (one render) | mean ΔE00 (frame) | mean ΔE00 (region) | frame ΔE00 × √s | region × √s |"
echo "|---|---|---|---|---|---|---|---|"
for scene in $scenes; do
  IFS='|' read -ra run_list <<<"$runs"
  for run in "${run_list[@]}"; do
    read -r integrator manifold guiding <<<"$run"
    guiding=${guiding:-off}
    total=0
    for seed in 1 2; do
      "$bin" render "$tmp/$scene-$manifold.json" --integrator "$integrator" --spp "$spp" --resolution "$resolution" \
        --threads "$threads" --seed "$seed" --guiding "$guiding" -o "$tmp/$seed.pfm" --stats-json "$tmp/s.json" --quiet
      s=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['seconds'])" "$tmp/s.json")
      total=$(echo "$total $s" | awk '{print $1 + $2}')
    done
    region="0.42 0.64 0.56 0.66"
    [[ $scene == ball ]] && region="0.30 0.70 0.20 0.75"
    [[ $scene == bounce ]] && region="0.0 1.0 0.0 1.0"
    [[ $scene == softbox ]] && region="0.35 0.65 0.45 0.70"
    read -r whole under < <(noise "$tmp/1.pfm" "$tmp/2.pfm" "$region")
    label=$integrator
    [[ $integrator == path ]] && label="path, manifold $manifold"
    [[ $guiding == on ]] && label="$label, guided"
    echo "$scene|$label|$spp|$total|$whole|$under" | awk -F'|' '{s = $4 / 2; printf "| %s | %s | %s | %.2f | %s | %s | %.3f | %.3f |\n", $1, $2, $3, s, $5, $6, $5 * sqrt(s), $6 * sqrt(s)}'
  done
done
