#!/usr/bin/env bash
# make choose: what --integrator auto (integrators/choose.h) rests on, measured. (1) Each
# estimator's seconds per ray on four showcases (64x48, 64 spp, one thread, seed 1), relative to
# the path tracer's: the geometric means are cost_per_ray's constants. (2) What auto chooses on
# each (64x48, 64 spp: trials of 4 spp) and its trials' figures. Writes both tables into
# docs/performance.md between the BENCH:choose markers. It reports; it asserts nothing.
set -euo pipefail
build=${1:-build}
doc=docs/performance.md
out=out/choose
mkdir -p "$out"
scenes=${CHOOSE_SCENES:-"coloured-caustics wine-on-table milk-and-juice diamond-fire"}
machine="$(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'))"
field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

table=$(
  echo "Measured on $(date -u +%Y-%m-%d), $machine, Release build, 64x48, 64 spp, full spectrum, one thread."
  echo
  echo "| scene | path ns/ray | bdpt ns/ray | vcm ns/ray | bdpt / path | vcm / path |"
  echo "|---|---|---|---|---|---|"
  bdpt_logs=() vcm_logs=()
  for name in $scenes; do
    row="| $name"
    declare -A ns=()
    for integrator in path bdpt vcm; do
      j=$out/$name-$integrator.json
      "$build/bouguer" render "scenes/showcase/$name.json" --integrator $integrator --spectral full --spp 64 --seed 1 \
        --resolution 64x48 --threads 1 -o "$out/$name-$integrator.pfm" --stats-json "$j" --quiet
      ns[$integrator]=$(field "$j" "1e9 * d['seconds'] / d['rays']")
      row="$row | $(printf '%.0f' "${ns[$integrator]}")"
    done
    b=$(awk -v a="${ns[bdpt]}" -v p="${ns[path]}" 'BEGIN { printf "%.3f", a / p }')
    v=$(awk -v a="${ns[vcm]}" -v p="${ns[path]}" 'BEGIN { printf "%.3f", a / p }')
    bdpt_logs+=("$b") vcm_logs+=("$v")
    echo "$row | $b | $v |"
  done
  gm() { printf '%s\n' "$@" | awk '{ s += log($1); n++ } END { printf "%.2f", exp(s / n) }'; }
  echo "| geometric mean | | | | $(gm "${bdpt_logs[@]}") | $(gm "${vcm_logs[@]}") |"
  echo
  echo "What \`--integrator auto\` chooses (64x48, 64 spp, seed 1, two threads; each trial 4 spp):"
  echo
  echo "Each trial: its own ΔE00 (at 4 spp), its cost, and its ΔE00 predicted at the cost of 64 spp of the cheapest (the score) with the samples that buys."
  echo
  echo "| scene | chosen | path ΔE00, cost, score | bdpt ΔE00, cost, score | vcm ΔE00, cost, score |"
  echo "|---|---|---|---|---|"
  for name in $scenes; do
    j=$out/$name-auto.json
    "$build/bouguer" render "scenes/showcase/$name.json" --integrator auto --spectral full --spp 64 --seed 1 \
      --resolution 64x48 --threads 2 -o "$out/$name-auto.pfm" --stats-json "$j" --quiet
    echo "| $name | $(field "$j" "d['auto']['chosen']") | $(field "$j" "' | '.join('misses light: not trialled' if t['rays'] == 0 else '%.2f, %.3g, %.2f at %.0f spp%s' % (t['error_delta_e00'], t['cost'], t['score'], t['samples_at_equal_cost'], ' (darker)' if t['darker'] else '') for t in d['auto']['trials'])") |"
  done
)
echo "$table"
awk -v body="$table" '
  $0 == "<!-- BENCH:choose:begin -->" { print; print body; skip = 1; next }
  $0 == "<!-- BENCH:choose:end -->" { skip = 0 }
  !skip { print }' "$doc" > "$doc.tmp" && mv "$doc.tmp" "$doc"
echo "choose: tables written to $doc"
