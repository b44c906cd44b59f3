#!/usr/bin/env bash
# make fuzz: builds the libFuzzer harnesses of the file readers (tests/fuzz) with clang, ASan and
# UBSan in BUILD, then runs each in turn for SECONDS on its committed corpus.
#   scripts/fuzz.sh [BUILD [SECONDS [TARGET...]]]     (defaults: build-fuzz, 180, all targets)
# Inputs that reach new code collect in BUILD/fuzz-corpus/<target> (not committed); a crash, a
# timeout or an allocation past the limits leaves its input in BUILD/fuzz-findings/<target>/ and
# makes the script fail. Minimise a finding (fuzz_<target> -minimize_crash=1 -runs=10000 FILE),
# fix it, and add it to tests/fuzz/corpus/<target>/found_<what>.<ext>.
# FUZZ_FLAGS adds libFuzzer options (e.g. FUZZ_FLAGS=-jobs=2).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-fuzz}
seconds=${2:-180}
shift $(( $# < 2 ? $# : 2 ))
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(spectrum_csv material_csv obj ply_ascii ply_binary exr pfm environment scene gltf texture mtl)

bash scripts/install-deps.sh --fuzz
# RelWithDebInfo without NDEBUG: assertions are findings too.
cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" -DBOUGUER_FUZZ=ON -DBOUGUER_BUILD_TESTS=OFF \
  -DBOUGUER_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --target bouguer_fuzzers -j "${JOBS:-2}"

# Each input is written to a scratch file (the readers take paths): in memory where there is /dev/shm.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
# The leaks that are not ours (tests/lsan.supp: fontconfig, OpenImageIO's PNG error path).
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
failed=()
summary=()
for t in "${targets[@]}"; do
  work="$build/fuzz-corpus/$t" findings="$build/fuzz-findings/$t"
  mkdir -p "$work" "$findings"
  # Keywords of the format (tests/fuzz/dict), shared between targets of one format.
  case "$t" in
    ply_*) parts=(ply) ;; spectrum_csv) parts=(csv) ;; material_csv) parts=(csv material_csv) ;;
    environment) parts=(exr pfm) ;; *) parts=("$t") ;;
  esac
  dict="$build/fuzz-$t.dict"
  : >"$dict"
  for p in "${parts[@]}"; do cat "tests/fuzz/dict/$p.dict" >>"$dict"; done
  log="$build/fuzz-$t.log"
  echo "fuzz: $t for ${seconds}s (log: $log)"
  set +e
  # shellcheck disable=SC2086
  "$build/tests/fuzz/fuzz_$t" "$work" "tests/fuzz/corpus/$t" -dict="$dict" -max_total_time="$seconds" \
    -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 -print_final_stats=1 \
    -artifact_prefix="$findings/" ${FUZZ_FLAGS:-} >"$log" 2>&1
  rc=$?
  set -e
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  took=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)
  summary+=("$(printf '%-13s %4ss %10s runs  exit %d' "$t" "${took:-?}" "${runs:-?}" "$rc")")
  if [ "$rc" -ne 0 ]; then
    failed+=("$t")
    grep -m3 -E "ERROR|SUMMARY|Test unit written" "$log" || tail -5 "$log"
  fi
done
printf '%s\n' "${summary[@]}"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in: ${failed[*]} (inputs in $build/fuzz-findings/)" >&2
  exit 1
fi
