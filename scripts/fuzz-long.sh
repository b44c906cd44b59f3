#!/usr/bin/env bash
# make fuzz-long: every reader's harness for SECONDS (default an hour each), as many at once as
# there are cores (FUZZ_LONG_JOBS overrides), then the summary table (target, seconds, executions,
# corpus size, findings) on stdout and in BUILD/fuzz-long-summary.md, for docs/limits.md.
#   scripts/fuzz-long.sh [BUILD [SECONDS [TARGET...]]]   (defaults: build-fuzz, 3600, all targets)
# FUZZ_NO_BUILD=1 runs the harnesses already in BUILD (or FUZZ_BIN, one binary for all targets:
# tests/fuzz/harness.cpp) without building: on a machine without the build's tools.
# Findings as with make fuzz (scripts/fuzz.sh): inputs in BUILD/fuzz-findings/<target>/.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/fuzz-lib.sh
build=${1:-build-fuzz}
seconds=${2:-3600}
shift $(( $# < 2 ? $# : 2 ))
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${fuzz_default_targets[@]}")
jobs=${FUZZ_LONG_JOBS:-$(nproc 2>/dev/null || echo 2)}

[ "${FUZZ_NO_BUILD:-0}" = 1 ] || fuzz_build "$build"
fuzz_environment
rows_dir="$build/fuzz-long-rows"
rm -rf "$rows_dir"
mkdir -p "$rows_dir"
echo "fuzz-long: ${#targets[@]} harnesses for ${seconds}s each, $jobs at once (logs: $build/fuzz-<target>.log)"
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
  ( fuzz_one "$build" "$seconds" "$t" >"$rows_dir/$t" || touch "$rows_dir/$t.failed" ) &
  running=$((running + 1))
done
wait || true
summary="$build/fuzz-long-summary.md"
{
  echo "fuzz-long on $(date -u +%Y-%m-%d), $(nproc) cores, ${seconds} s per harness, commit $(git rev-parse --short HEAD 2>/dev/null || echo '?'):"
  echo
  fuzz_table_head
  for t in "${targets[@]}"; do cat "$rows_dir/$t"; done
} >"$summary"
cat "$summary"
failed=$(cd "$rows_dir" && { ls -- *.failed 2>/dev/null || true; } | sed 's/\.failed$//' | tr '\n' ' ')
if [ -n "$failed" ]; then
  echo "fuzz-long: findings in: $failed(inputs in $build/fuzz-findings/)" >&2
  exit 1
fi
