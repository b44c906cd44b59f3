#!/usr/bin/env bash
# make bench: runs the benchmarks and writes their figures into docs/performance.md (between the
# BENCH markers). Benchmarks report; they never fail on a time.
set -euo pipefail
build=${1:-build}
mkdir -p out/bench
"$build/bench/bouguer_bench" --benchmark_out=out/bench/micro.csv --benchmark_out_format=csv
table=$(awk -F, '
  /^name,/ { started = 1; next }
  started && NF > 4 {
    gsub(/"/, "", $1)
    printf "| %s | %.1f | %s |\n", $1, $4, ($7 == "" ? "" : sprintf("%.3g wavelengths/s", $7))
  }' out/bench/micro.csv)
machine="$(nproc) cores, $(uname -m), $(date -u +%Y-%m-%d)"
doc=docs/performance.md
{
  sed -n '1,/<!-- BENCH:micro:begin -->/p' "$doc"
  echo "Measured on: $machine (Release build)."
  echo
  echo "| benchmark | ns per call (real) | throughput |"
  echo "|---|---|---|"
  echo "$table"
  sed -n '/<!-- BENCH:micro:end -->/,$p' "$doc"
} > "$doc.tmp" && mv "$doc.tmp" "$doc"
echo "bench: figures written to $doc"
