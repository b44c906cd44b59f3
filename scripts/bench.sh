#!/usr/bin/env bash
# make bench: the micro-benchmarks and the paper's scenes at fixed settings (512x512, 16 spp, both
# spectral modes, all cores); the figures go into docs/performance.md between the BENCH markers.
# Benchmarks report; they never fail on a time.
# BENCH_BASELINE=path/to/an/older/bouguer adds its time for each row, rendered alternately with the
# current build's on the same machine, and the change (for "no scene slower by more than 5 %").
# BENCH_SECTIONS picks some of "micro scenes showcase mesh" (default all).
# BENCH_RUNS=N renders each row N times and keeps the fastest (default 3 with a baseline, else 1).
set -euo pipefail
build=${1:-build}
doc=docs/performance.md
mkdir -p out/bench
machine="$(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'))"
today=$(date -u +%Y-%m-%d)

# Replaces the lines between <!-- BENCH:$1:begin --> and <!-- BENCH:$1:end --> with stdin.
replace_section() {
  local body
  body=$(cat)
  awk -v tag="$1" -v body="$body" '
    $0 == "<!-- BENCH:" tag ":begin -->" { print; print body; skip = 1; next }
    $0 == "<!-- BENCH:" tag ":end -->" { skip = 0 }
    !skip { print }' "$doc" > "$doc.tmp" && mv "$doc.tmp" "$doc"
}

sections=${BENCH_SECTIONS:-micro scenes showcase mesh}
wants() { [[ " $sections " == *" $1 "* ]]; }

if wants micro; then
"$build/bench/bouguer_bench" --benchmark_out=out/bench/micro.csv --benchmark_out_format=csv
{
  echo "Measured on $today, $machine, Release build."
  echo
  echo "| benchmark | ns per call (real) | throughput |"
  echo "|---|---|---|"
  awk -F, '
    /^name,/ { started = 1; next }
    started && NF > 4 {
      gsub(/"/, "", $1)
      printf "| %s | %.1f | %s |\n", $1, $3, ($7 == "" ? "" : sprintf("%.3g wavelengths/s", $7))
    }' out/bench/micro.csv
} | replace_section micro
fi

# Renders every scene of a glob in each spectral mode at fixed settings; prints a table.
# bench_table GLOB WIDTHxHEIGHT SPP "MODES" [extra render flags...]
bench_table() {
  local glob=$1 resolution=$2 spp=$3 modes=$4
  shift 4
  local extra=("$@")
  local baseline=${BENCH_BASELINE:-}
  local runs=${BENCH_RUNS:-$([ -n "$baseline" ] && echo 3 || echo 1)}
  echo "Measured on $today, $machine, Release build; \`bouguer render SCENE ${*:+$* }--resolution $resolution --spp $spp\`."
  if [ "$runs" -gt 1 ]; then echo "Each time is the fastest of $runs runs${baseline:+, the baseline's and the current build's alternating}."; fi
  echo
  if [ -n "$baseline" ]; then
    echo "Baseline: \`$baseline\` (each of its runs just before one of the current build's)."
    echo
    echo "| scene | spectral | resolution | spp | seconds | baseline seconds | change | rays | rays/s |"
    echo "|---|---|---|---|---|---|---|---|---|"
  else
    echo "| scene | spectral | resolution | spp | seconds | rays | rays/s |"
    echo "|---|---|---|---|---|---|---|"
  fi
  for scene in $glob; do
    local name
    name=$(basename "$scene" .json)
    # Whole milk takes about an hour a mode at 480x360, 64 spp: timed on its own in
    # docs/performance.md ("Showcases of #20").
    [ "$name" = milk-and-juice ] && continue
    for mode in $modes; do
      local rays rays_per_second seconds="" base_seconds="" s run
      # Baseline and current alternate, run after run; each column keeps its fastest run.
      for ((run = 0; run < runs; run++)); do
        # A baseline that cannot read the scene (a feature newer than it) leaves its column empty.
        if [ -n "$baseline" ] && [ "$base_seconds" != "-" ]; then
          if read -r _ _ s < <(render_stats "$baseline" "$scene" "$mode" "$resolution" "$spp" base "${extra[@]}" 2>/dev/null); then
            base_seconds=$(fastest "$base_seconds" "$s")
          else
            base_seconds="-"
          fi
        fi
        read -r rays rays_per_second s < <(render_stats "$build/bouguer" "$scene" "$mode" "$resolution" "$spp" new "${extra[@]}")
        seconds=$(fastest "$seconds" "$s")
      done
      rays_per_second=$(echo "$rays $seconds" | awk '{printf "%.6g", $1 / $2}')
      if [ -n "$baseline" ]; then
        if [ "$base_seconds" = "-" ]; then
          printf '| %s | %s | %s | %s | %.2f | - | - | %s | %.3g |\n' "$name" "$mode" "$resolution" "$spp" "$seconds" \
            "$rays" "$rays_per_second"
        else
          printf '| %s | %s | %s | %s | %.2f | %.2f | %+.1f %% | %s | %.3g |\n' "$name" "$mode" "$resolution" "$spp" \
            "$seconds" "$base_seconds" "$(echo "$seconds $base_seconds" | awk '{print 100 * ($1 / $2 - 1)}')" "$rays" \
            "$rays_per_second"
        fi
      else
        printf '| %s | %s | %s | %s | %.2f | %s | %.3g |\n' "$name" "$mode" "$resolution" "$spp" "$seconds" "$rays" \
          "$rays_per_second"
      fi
    done
  done
}

# The smaller of two times; the first may be empty.
fastest() { if [ -z "$1" ]; then echo "$2"; else echo "$1 $2" | awk '{print ($1 < $2 ? $1 : $2)}'; fi; }

# render_stats BINARY SCENE MODE RESOLUTION SPP TAG [flags...]: prints "rays rays_per_second seconds".
render_stats() {
  local binary=$1 scene=$2 mode=$3 resolution=$4 spp=$5 tag=$6
  shift 6
  local name stats
  name=$(basename "$scene" .json)
  stats=out/bench/$name-$mode-$tag.json
  "$binary" render "$scene" "$@" --spectral "$mode" --resolution "$resolution" --spp "$spp" \
    -o "out/bench/$name-$mode-$tag.exr" --stats-json "$stats" --quiet
  # --stats-json keys come sorted: integrator, rays, rays_per_second, resolution, seconds, ...
  tr -d '\n ' < "$stats" | sed -E 's/.*"rays":([0-9]+),"rays_per_second":([0-9.e+]+),.*"seconds":([0-9.e+-]+),.*/\1 \2 \3\n/'
}

if wants scenes; then bench_table "scenes/paper/*.json" 512x512 16 "full rgb3" | replace_section scenes; fi
if wants showcase; then
  bench_table "scenes/showcase/*.json" 480x360 64 "full hero" --integrator path | replace_section showcase
fi
if wants mesh; then
  {
    echo "Measured on $today, $machine, Release build, on a machine shared with other work;"
    echo "\`$build/bench/bouguer_bench_mesh\` (bench/bench_mesh_setup.cpp), the fastest of BENCH_RUNS (${BENCH_RUNS:-3})."
    echo
    BENCH_RUNS=${BENCH_RUNS:-3} "$build/bench/bouguer_bench_mesh"
  } | replace_section mesh
fi
echo "bench: figures written to $doc"
