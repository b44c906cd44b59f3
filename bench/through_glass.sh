#!/usr/bin/env bash
# Next-event estimation through glass at surfaces (#20, docs/rendering.md), for one or more builds
# of bouguer: each scene rendered with seeds 1 and 2, their render times and the mean ΔE00 between
# the two (the noise), and for studio-glassware also against a long reference of the first build.
# The scenes, all under the studio map:
#   cup      a diffuse ball in a glass cup beside a tumbler of red wine (the scene of
#            tests/statistical/test_through_glass.cpp), 96x96, 128 spp
#   studio   scenes/examples/studio-glassware.json, 240x160, 64 spp (reference: 2048 spp, seed 1000)
#   empty    scenes/showcase/milk-and-juice.json with empty tumblers, 120x90, 32 spp
#   clear    the same filled with clear water, 120x90, 32 spp
#   milk     milk-and-juice itself, 120x90, 32 spp
#   skimmed  scenes/showcase/glass-of-milk.json, 48x36, 256 spp
# Reports only; the figures are in docs/performance.md.
#   bench/through_glass.sh build/bouguer [/path/to/other/bouguer ...]
# THREADS (2), REF_SPP (2048) and SCENES (all of the above) may be set.
set -euo pipefail
threads=${THREADS:-2}
ref_spp=${REF_SPP:-2048}
scenes=${SCENES:-"cup studio empty clear milk skimmed"}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$repo" "$tmp" <<'PY'
import json, os, sys
repo, out = sys.argv[1], sys.argv[2]
studio = os.path.join(repo, "scenes/examples/studio.pfm")
def load(rel):
    scene = json.load(open(os.path.join(repo, rel)))
    here = os.path.dirname(os.path.join(repo, rel))
    scene["background"]["environment"] = os.path.normpath(os.path.join(here, scene["background"]["environment"]))
    return scene
def save(name, scene):
    json.dump(scene, open(os.path.join(out, name + ".json"), "w"), indent=1)
save("studio", load("scenes/examples/studio-glassware.json"))
save("skimmed", load("scenes/showcase/glass-of-milk.json"))
milk = load("scenes/showcase/milk-and-juice.json")
save("milk", milk)
clear = json.loads(json.dumps(milk))
clear["media"]["clear"] = {"ior": 1.33}
for o in clear["objects"]:
    if "contents" in o:
        o["contents"] = "clear"
save("clear", clear)
empty = json.loads(json.dumps(milk))
for o in empty["objects"]:
    o.pop("contents", None)
    o["shape"].pop("fill", None)
save("empty", empty)
save("cup", {
    "camera": {"position": [0, "60 mm", "150 mm"], "look_at": [0, "30 mm", 0], "fov_deg": 30, "resolution": [96, 96]},
    "render": {"integrator": "path", "spectral": "full", "spp": 128, "max_depth": 200},
    "world_medium": "vacuum",
    "media": {"cup": {"ior": 1.5}, "glass": {"ior": 1.5}, "liquid": {"absorption": {"library": "red-wine"}}},
    "objects": [
        {"name": "cup", "shape": {"type": "vessel", "wall": "3 mm", "segments": 64,
                                  "profile": [[0, 0], ["30 mm", 0], ["32 mm", "3 mm"], ["34 mm", "60 mm"]]},
         "inside": "cup"},
        {"name": "ball", "shape": {"type": "sphere", "radius": "15 mm"}, "transform": [{"translate": [0, "25 mm", 0]}],
         "material": {"type": "diffuse", "reflectance": 0.8}},
        {"name": "wine", "shape": {"type": "vessel", "wall": "2 mm", "fill": 0.7, "segments": 48,
                                   "profile": [[0, 0], ["15 mm", 0], ["16 mm", "2 mm"], ["17 mm", "50 mm"]]},
         "transform": [{"translate": ["45 mm", 0, "-30 mm"]}], "inside": "glass", "contents": "liquid"}],
    "background": {"environment": studio}})
PY
size() { case $1 in cup) echo "96x96 128" ;; studio) echo "240x160 64" ;; skimmed) echo "48x36 256" ;; *) echo "120x90 32" ;; esac; }
seconds() { python3 -c "import json,sys; print('%.2f' % json.load(open(sys.argv[1]))['seconds'])" "$1"; }
mean_de() { "$first" compare "$1" "$2" | sed -n 's/.*mean \([0-9.]*\).*/\1/p'; }
first=$(realpath "$1")
if [[ " $scenes " == *" studio "* ]]; then
  "$first" render "$tmp/studio.json" --resolution 240x160 --spp "$ref_spp" --seed 1000 --threads "$threads" --quiet \
    -o "$tmp/studio-reference.pfm"
fi
echo "| build | scene | seconds (seeds 1, 2) | mean ΔE00 seed 1 to seed 2 | mean ΔE00 to the reference |"
echo "|---|---|---|---|---|"
for bin in "$@"; do
  bin=$(realpath "$bin")
  for scene in $scenes; do
    read -r resolution spp < <(size "$scene")
    for seed in 1 2; do
      "$bin" render "$tmp/$scene.json" --resolution "$resolution" --spp "$spp" --seed "$seed" --threads "$threads" \
        --quiet -o "$tmp/r$seed.pfm" --stats-json "$tmp/r$seed.stats"
    done
    ref=-
    [ "$scene" = studio ] && ref=$(mean_de "$tmp/r1.pfm" "$tmp/studio-reference.pfm")
    echo "| $bin | $scene ($resolution, $spp spp) | $(seconds "$tmp/r1.stats"), $(seconds "$tmp/r2.stats") |" \
      "$(mean_de "$tmp/r1.pfm" "$tmp/r2.pfm") | $ref |"
  done
done
