#!/usr/bin/env bash
# make estimators: for scenes where light reaches diffuse surfaces through glass (caustics), the
# seconds each estimator (path, bdpt, vcm) needs to reach mean CIEDE2000 < 2 and < 1 against a long
# reference, all in one run on one machine. The reference is the bidirectional estimator at
# ESTIMATORS_REFERENCE_SPP (another seed); each estimator renders 4, 8, 16, ... spp (seed 1) until
# both thresholds are met or the next render would pass ESTIMATORS_SPP_MAX. Small resolution: the
# per-pixel noise depends on the samples per pixel, not on the image size. Writes the table into
# docs/performance.md between the BENCH:estimators markers. It reports; it asserts nothing.
set -euo pipefail
build=${1:-build}
doc=docs/performance.md
out=out/estimators
mkdir -p "$out"
resolution=${ESTIMATORS_RESOLUTION:-64x48}
reference_spp=${ESTIMATORS_REFERENCE_SPP:-8192}
spp_max=${ESTIMATORS_SPP_MAX:-8192}
scenes=${ESTIMATORS_SCENES:-"coloured-caustics wine-on-table diamond-fire-on-a-card diamond-fire"}
machine="$(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'))"
seconds_of() { tr -d '\n ' < "$1" | sed -E 's/.*"seconds":([0-9.e+-]+),.*/\1\n/'; }
mean_of() { echo "$1" | sed -E 's/.*"mean":([^,}]*).*/\1/'; }

table=$(
  echo "Measured on $(date -u +%Y-%m-%d), $machine, Release build, $resolution, full spectrum."
  echo "Reference: \`bdpt\`, $reference_spp spp, seed 1000. Each cell: seconds (spp) of the first"
  echo "power-of-two render, seed 1, whose mean ΔE00 against the reference is below the threshold."
  echo
  echo "| scene | reference s | estimator | to ΔE00 < 2 | to ΔE00 < 1 | ΔE00 at the last render |"
  echo "|---|---|---|---|---|---|"
  for name in $scenes; do
    scene=scenes/showcase/$name.json
    ref=$out/$name-reference.exr
    "$build/bouguer" render "$scene" --integrator bdpt --spectral full --spp "$reference_spp" --seed 1000 \
      --resolution "$resolution" -o "$ref" --stats-json "$out/$name-reference.json" --quiet
    ref_seconds=$(seconds_of "$out/$name-reference.json")
    for integrator in path bdpt vcm; do
      two="-" one="-" last="-"
      for spp in 4 8 16 32 64 128 256 512 1024 2048 4096 8192 16384 32768; do
        [ "$spp" -gt "$spp_max" ] && break
        img=$out/$name-$integrator-$spp.exr
        "$build/bouguer" render "$scene" --integrator $integrator --spectral full --spp $spp --seed 1 \
          --resolution "$resolution" -o "$img" --stats-json "$out/$name-$integrator-$spp.json" --quiet
        mean=$(mean_of "$("$build/bouguer" compare "$img" "$ref" --json)")
        seconds=$(seconds_of "$out/$name-$integrator-$spp.json")
        last=$(printf '%.2f (%s spp)' "$mean" "$spp")
        if [ "$two" = "-" ] && awk -v m="$mean" 'BEGIN { exit !(m < 2.0) }'; then two=$(printf '%.1f s (%s)' "$seconds" "$spp"); fi
        if awk -v m="$mean" 'BEGIN { exit !(m < 1.0) }'; then one=$(printf '%.1f s (%s)' "$seconds" "$spp"); break; fi
      done
      printf '| %s | %.0f | %s | %s | %s | %s |\n' "$name" "$ref_seconds" "$integrator" "$two" "$one" "$last" >&2
      printf '| %s | %.0f | %s | %s | %s | %s |\n' "$name" "$ref_seconds" "$integrator" "$two" "$one" "$last"
    done
  done
)
awk -v body="$table" '
  $0 == "<!-- BENCH:estimators:begin -->" { print; print body; skip = 1; next }
  $0 == "<!-- BENCH:estimators:end -->" { skip = 0 }
  !skip { print }' "$doc" > "$doc.tmp" && mv "$doc.tmp" "$doc"
echo "estimators: table written to $doc"
