#!/usr/bin/env bash
# make fuzz: builds the libFuzzer harnesses of the file readers (tests/fuzz) with clang, ASan and
# UBSan in BUILD, then runs each in turn for SECONDS on its committed corpus (scripts/fuzz-lib.sh).
#   scripts/fuzz.sh [BUILD [SECONDS [TARGET...]]]     (defaults: build-fuzz, 180, all targets)
# Inputs that reach new code collect in BUILD/fuzz-corpus/<target> (not committed); a crash, a
# timeout or an allocation past the limits leaves its input in BUILD/fuzz-findings/<target>/ and
# makes the script fail. Minimise a finding (fuzz_<target> -minimize_crash=1 -runs=10000 FILE),
# fix it, and add it to tests/fuzz/corpus/<target>/found_<what>.<ext>.
# FUZZ_FLAGS adds libFuzzer options (e.g. FUZZ_FLAGS=-jobs=2). make fuzz-long runs them in parallel.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/fuzz-lib.sh
build=${1:-build-fuzz}
seconds=${2:-180}
shift $(( $# < 2 ? $# : 2 ))
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${fuzz_default_targets[@]}")

fuzz_build "$build"
fuzz_environment
failed=()
rows=()
for t in "${targets[@]}"; do
  echo "fuzz: $t for ${seconds}s (log: $build/fuzz-$t.log)"
  if row=$(fuzz_one "$build" "$seconds" "$t"); then rows+=("$row"); else rows+=("$row"); failed+=("$t"); fi
done
fuzz_table_head
printf '%s\n' "${rows[@]}"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in: ${failed[*]} (inputs in $build/fuzz-findings/)" >&2
  exit 1
fi
