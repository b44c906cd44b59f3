#!/usr/bin/env bash
# vcm's light subpaths kept once per iteration (#37): each iteration traces one light subpath per
# pixel, makes its photons from it and keeps it for that pixel's connections, where vcm traced it
# again until 2026-12-05. Per scene: the wall seconds of the fastest of three runs, the rays, the
# peak resident memory (GNU time's %M) and the light subpaths' memory (--stats-json's
# vcm.light_subpath_bytes, the most an iteration kept). With a second binary (a build from before
# the change) the two alternate and a row compares them. Reports only; the figures are in
# docs/performance.md ("vcm's light subpaths").
#   bench/vcm_light_subpaths.sh build/bouguer [OTHER_BOUGUER]
# RESOLUTION (160x120), SPP (16) and THREADS (2) may be set.
set -euo pipefail
bin=${1:-build/bouguer}
other=${2:-}
resolution=${RESOLUTION:-160x120}
spp=${SPP:-16}
threads=${THREADS:-2}
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
command -v /usr/bin/time >/dev/null || { echo "vcm_light_subpaths.sh: needs GNU time (/usr/bin/time)" >&2; exit 1; }

# name | scene | extra options
cases=(
  "coloured-caustics|scenes/showcase/coloured-caustics.json|"
  "coloured-caustics, hero|scenes/showcase/coloured-caustics.json|--spectral hero"
  "wine-on-table|scenes/showcase/wine-on-table.json|"
  "milk-and-juice|scenes/showcase/milk-and-juice.json|"
  "diamond-fire-on-a-card|scenes/showcase/diamond-fire-on-a-card.json|"
  "lit tumbler|tests/data/lit_tumbler/scene.json|"
)

# run BIN SCENE EXTRA TAG: one render; prints "seconds rays peak_kib light_subpath_bytes"
run() {
  local j="$tmp/$4.json"
  # shellcheck disable=SC2086
  /usr/bin/time -f "%M" -o "$tmp/$4.time" "$1" render "$repo/$2" $3 --integrator vcm --resolution "$resolution" \
    --spp "$spp" --threads "$threads" --seed 1 -o "$tmp/$4.pfm" --stats-json "$j" --quiet
  python3 - "$j" "$tmp/$4.time" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
peak = open(sys.argv[2]).read().split()[-1]
print(d["seconds"], d["rays"], peak, d["vcm"].get("light_subpath_bytes", 0))
PY
}

echo "Measured on $(date -u +%Y-%m-%d), $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')), Release, $resolution, $spp iterations, $threads threads, seed 1; the fastest of three runs${other:+, alternating with $other}."
echo
if [[ -n $other ]]; then
  echo "| scene | seconds | before | rays | before | peak memory | before | light subpaths kept |"
  echo "|---|---|---|---|---|---|---|---|"
else
  echo "| scene | seconds | rays | peak memory | light subpaths kept |"
  echo "|---|---|---|---|---|"
fi
for c in "${cases[@]}"; do
  IFS='|' read -r name scene extra <<<"$c"
  best_new="" best_old=""
  for i in 1 2 3; do
    new=$(run "$bin" "$scene" "$extra" new)
    [[ -z $best_new || $(awk -v a="${new%% *}" -v b="${best_new%% *}" 'BEGIN{print (a<b)}') == 1 ]] && best_new=$new
    if [[ -n $other ]]; then
      old=$(run "$other" "$scene" "$extra" old)
      [[ -z $best_old || $(awk -v a="${old%% *}" -v b="${best_old%% *}" 'BEGIN{print (a<b)}') == 1 ]] && best_old=$old
    fi
  done
  read -r s r m k <<<"$best_new"
  mib() { awk -v x="$1" -v d="$2" 'BEGIN { printf "%.0f MiB", x / d }'; }
  if [[ -n $other ]]; then
    read -r s0 r0 m0 k0 <<<"$best_old"
    printf '| %s | %.2f | %.2f | %s | %s | %s | %s | %s |\n' "$name" "$s" "$s0" "$r" "$r0" "$(mib "$m" 1024)" \
      "$(mib "$m0" 1024)" "$(mib "$k" 1048576)"
  else
    printf '| %s | %.2f | %s | %s | %s |\n' "$name" "$s" "$r" "$(mib "$m" 1024)" "$(mib "$k" 1048576)"
  fi
done
