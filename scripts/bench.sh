#!/usr/bin/env bash
# make bench: the micro-benchmarks and the paper's scenes at fixed settings (512x512, 16 spp, both
# spectral modes, all cores); the figures go into docs/performance.md between the BENCH markers.
# Benchmarks report; they never fail on a time.
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

{
  echo "Measured on $today, $machine, Release build; \`bouguer render SCENE --resolution 512x512 --spp 16\`."
  echo
  echo "| scene | spectral | resolution | spp | seconds | rays | rays/s |"
  echo "|---|---|---|---|---|---|---|"
  for scene in scenes/paper/*.json; do
    name=$(basename "$scene" .json)
    for mode in full rgb3; do
      stats=out/bench/$name-$mode.json
      "$build/bouguer" render "$scene" --spectral "$mode" --resolution 512x512 --spp 16 \
        -o "out/bench/$name-$mode.exr" --stats-json "$stats" --quiet
      # --stats-json keys come sorted: rays, rays_per_second, resolution, seconds, ...
      set -- $(tr -d '\n ' < "$stats" |
        sed -E 's/.*"rays":([0-9]+),"rays_per_second":([0-9.e+]+),.*"seconds":([0-9.e+-]+),.*/\1 \2 \3/')
      printf '| %s | %s | 512x512 | 16 | %.2f | %s | %.3g |\n' "$name" "$mode" "$3" "$1" "$2"
    done
  done
} | replace_section scenes

{
  echo "Measured on $today, $machine, Release build; \`bouguer render SCENE --integrator path --resolution 480x360 --spp 64\`."
  echo
  echo "| scene | spectral | resolution | spp | seconds | rays | rays/s |"
  echo "|---|---|---|---|---|---|---|"
  for scene in scenes/showcase/*.json; do
    name=$(basename "$scene" .json)
    for mode in full hero; do
      stats=out/bench/$name-$mode.json
      "$build/bouguer" render "$scene" --integrator path --spectral "$mode" --resolution 480x360 --spp 64 \
        -o "out/bench/$name-$mode.exr" --stats-json "$stats" --quiet
      set -- $(tr -d '\n ' < "$stats" |
        sed -E 's/.*"rays":([0-9]+),"rays_per_second":([0-9.e+]+),.*"seconds":([0-9.e+-]+),.*/\1 \2 \3/')
      printf '| %s | %s | 480x360 | 64 | %.2f | %s | %.3g |\n' "$name" "$mode" "$3" "$1" "$2"
    done
  done
} | replace_section showcase
echo "bench: figures written to $doc"
