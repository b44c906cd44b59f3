# shellcheck shell=bash disable=SC2154,SC2004
# Sourced by the bench scripts that compare settings or builds by pairs of seeds
# (bench/shell_transport.sh, bench/dense_connections.sh). The caller sets tmp, resolution, spp and
# threads, and declares the associative arrays secs and gaps.
#
# render_pair TAG BIN SCENE PAIR: renders SCENE with BIN at seeds 2·PAIR − 1 and 2·PAIR, adds the
# seconds of each (its --stats-json, wall clock) to secs[TAG] and the mean ΔE00 between the two
# (about √2 times one render's error: noise only) to gaps[TAG].
render_pair() {
  local tag=$1 bin=$2 scene=$3 pair=$4 seed
  for seed in $((2 * pair - 1)) $((2 * pair)); do
    "$bin" render "$scene" --resolution "$resolution" --spp "$spp" --seed "$seed" --threads "$threads" --quiet \
      -o "$tmp/r-$tag-$seed.pfm" --stats-json "$tmp/s-$tag-$seed.json"
    secs[$tag]="${secs[$tag]:-} $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['seconds'])" \
      "$tmp/s-$tag-$seed.json")"
  done
  gaps[$tag]="${gaps[$tag]:-} $("$bin" compare "$tmp/r-$tag-$((2 * pair - 1)).pfm" "$tmp/r-$tag-$((2 * pair)).pfm" |
    sed -n 's/.*mean \([0-9.]*\).*/\1/p')"
}

# pair_row SCENE WHAT TAG: the table row of TAG's renders: the mean seconds (range), the mean gap
# (each pair's) and ΔE00² × seconds (lower is better).
pair_row() {
  python3 - "$1" "$2" "${secs[$3]}" "${gaps[$3]}" <<'PY'
import sys
s = [float(x) for x in sys.argv[3].split()]
g = [float(x) for x in sys.argv[4].split()]
ms, mg = sum(s) / len(s), sum(g) / len(g)
print(f"| {sys.argv[1]} | {sys.argv[2]} | {ms:.2f} ({min(s):.2f}–{max(s):.2f}) | "
      f"{mg:.2f} ({' '.join(f'{x:.2f}' for x in g)}) | {mg * mg * ms:.3g} |")
PY
}
