#!/usr/bin/env bash
# make demo: renders the paper's scenes (scenes/paper) in full spectrum and in the paper's RGB
# approach (rgb3), puts each pair side by side with its CIEDE2000 heat map, and tabulates the
# colour differences in out/summary.md. With BOUGUER_UPDATE_DOCS=1 it also refreshes the README's
# images in docs/images.
set -euo pipefail
build=${1:-build}
bouguer="$build/bouguer"
mkdir -p out
summary=out/summary.md
{
  echo "# Bouguer demo: the paper's scenes, full spectrum against RGB (rgb3)"
  echo
  echo "Each image: full spectrum | rgb3 (700.0, 546.1, 435.8 nm) | CIEDE2000 heat map (black 0, white >= 10)."
  echo
  echo "| scene | full: seconds | rgb3: seconds | mean ΔE00 | p95 ΔE00 | max ΔE00 |"
  echo "|---|---|---|---|---|---|"
} > "$summary"
for scene in scenes/paper/*.json; do
  name=$(basename "$scene" .json)
  for mode in full rgb3; do
    "$bouguer" render "$scene" --spectral "$mode" -o "out/$name-$mode.exr" -o "out/$name-$mode.png" \
      --stats-json "out/$name-$mode.json" --quiet
  done
  diff_json=$("$bouguer" compare "out/$name-full.exr" "out/$name-rgb3.exr" --montage "out/$name.png" --json)
  field() { echo "$2" | sed -E "s/.*\"$1\":([^,}]*).*/\1/"; }
  seconds() { sed -nE 's/.*"seconds": ([0-9.]+).*/\1/p' "$1"; }
  printf '| %s | %.2f | %.2f | %.2f | %.2f | %.2f |\n' "$name" "$(seconds "out/$name-full.json")" \
    "$(seconds "out/$name-rgb3.json")" "$(field mean "$diff_json")" "$(field p95 "$diff_json")" \
    "$(field max "$diff_json")" >> "$summary"
  echo "demo: $name -> out/$name.png (mean ΔE00 $(field mean "$diff_json"))"
  if [ "${BOUGUER_UPDATE_DOCS:-0}" = 1 ]; then
    mkdir -p docs/images
    cp "out/$name.png" "docs/images/$name.png"
  fi
done
echo "demo: summary in $summary"
cat "$summary"
# The same scenes once more, as one self-contained page (opens offline): images, heat maps, the
# materials' plots, settings and times.
"$bouguer" report --out out/report --scenes scenes/paper --quiet
echo "demo: report in out/report/index.html"
