#!/usr/bin/env bash
# make convergence: for each showcase scene, the samples per pixel and seconds that the full and
# hero modes need to reach mean CIEDE2000 < 1 against a long reference render (full, 32768 spp,
# another seed). Writes the table into docs/performance.md between the BENCH:convergence markers.
# The resolution is small (96×72) so that a reference with little noise of its own fits in minutes
# on 2 cores: per-pixel noise depends on the samples per pixel, not on the resolution.
set -euo pipefail
build=${1:-build}
doc=docs/performance.md
mkdir -p out/convergence
machine="$(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'))"
resolution=96x72
reference_spp=32768
# Slow scenes (scattering media) may be measured smaller: CONVERGENCE_SMALL="a b" renders those at
# 48x36 against a 4096-spp reference; their rows say so.
small_resolution=48x36
small_reference_spp=4096

seconds_of() { tr -d '\n ' < "$1" | sed -E 's/.*"seconds":([0-9.e+-]+),.*/\1\n/'; }
mean_of() { echo "$1" | sed -E 's/.*"mean":([^,}]*).*/\1/'; }

table=$(
  echo "Measured on $(date -u +%Y-%m-%d), $machine, Release build; $resolution, \`--integrator path\`;"
  echo "reference: full, $reference_spp spp, seed 1000. A mode's row: the first power-of-two spp whose"
  echo "render (seed 1) has mean ΔE00 < 1 against the reference.${CONVERGENCE_SCENES:+ Only $CONVERGENCE_SCENES were measured on this date; the other rows are kept from earlier runs.}"
  echo
  echo "| scene | reference seconds | mode | spp to ΔE00 < 1 | seconds | mean ΔE00 there |"
  echo "|---|---|---|---|---|---|"
  for scene in scenes/showcase/*.json; do
    name=$(basename "$scene" .json)
    row=out/convergence/$name.rows
    # CONVERGENCE_SCENES="a b" measures only those scenes and keeps the other rows from earlier runs.
    if [ -n "${CONVERGENCE_SCENES:-}" ] && [[ " $CONVERGENCE_SCENES " != *" $name "* ]]; then
      # Its rows from an earlier run: the cached file, else the table in the document.
      if [ -f "$row" ]; then cat "$row"; else
        awk '/<!-- BENCH:convergence:begin -->/ { on = 1 } /<!-- BENCH:convergence:end -->/ { on = 0 } on' "$doc" |
          grep -E "^\| $name( |\|)" || true
      fi
      continue
    fi
    res=$resolution ref_spp=$reference_spp label=$name
    if [[ " ${CONVERGENCE_SMALL:-} " == *" $name "* ]]; then
      res=$small_resolution ref_spp=$small_reference_spp label="$name ($small_resolution, reference $small_reference_spp spp)"
    fi
    : > "$row.tmp"
    ref=out/convergence/$name-reference.exr
    "$build/bouguer" render "$scene" --integrator path --spectral full --spp $ref_spp --seed 1000 \
      --resolution $res -o "$ref" --stats-json out/convergence/$name-reference.json --quiet
    ref_seconds=$(seconds_of out/convergence/$name-reference.json)
    for mode in full hero; do
      found="> 8192 | - | -"
      for spp in 4 8 16 32 64 128 256 512 1024 2048 4096 8192; do
        img=out/convergence/$name-$mode-$spp.exr
        "$build/bouguer" render "$scene" --integrator path --spectral $mode --spp $spp --seed 1 \
          --resolution $res -o "$img" --stats-json out/convergence/$name-$mode-$spp.json --quiet
        mean=$(mean_of "$("$build/bouguer" compare "$img" "$ref" --json)")
        if awk -v m="$mean" 'BEGIN { exit !(m < 1.0) }'; then
          found=$(printf '%s | %.2f | %.3f' "$spp" "$(seconds_of out/convergence/$name-$mode-$spp.json)" "$mean")
          break
        fi
      done
      printf '| %s | %.1f | %s | %s |\n' "$label" "$ref_seconds" "$mode" "$found" | tee -a "$row.tmp"
    done
    mv "$row.tmp" "$row"
  done
)
awk -v body="$table" '
  $0 == "<!-- BENCH:convergence:begin -->" { print; print body; skip = 1; next }
  $0 == "<!-- BENCH:convergence:end -->" { skip = 0 }
  !skip { print }' "$doc" > "$doc.tmp" && mv "$doc.tmp" "$doc"
echo "convergence: table written to $doc"
