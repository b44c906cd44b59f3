# Sourced by scripts/fuzz.sh (make fuzz) and scripts/fuzz-long.sh (make fuzz-long): the list of
# harnesses, their build (clang, libFuzzer, ASan, UBSan) and one harness's run with its summary row.

# Every reader's harness (tests/fuzz/CMakeLists.txt builds fuzz_<name> for each).
fuzz_default_targets=(spectrum_csv material_csv obj ply_ascii ply_binary exr pfm environment scene vdb gltf texture
                      mtl)

# fuzz_build BUILD: configures and builds the harnesses in BUILD.
fuzz_build() {
  local build=$1
  bash scripts/install-deps.sh --fuzz
  # RelWithDebInfo without NDEBUG: assertions are findings too.
  cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" -DBOUGUER_FUZZ=ON -DBOUGUER_BUILD_TESTS=OFF \
    -DBOUGUER_BUILD_BENCH=OFF >/dev/null
  cmake --build "$build" --target bouguer_fuzzers -j "${JOBS:-2}"
}

fuzz_environment() {
  # Each input is written to a scratch file (the readers take paths): in memory where there is /dev/shm.
  if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
  # The leaks that are not ours (tests/lsan.supp: fontconfig, OpenImageIO's PNG error path).
  export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
}

fuzz_table_head() {
  echo "| target | seconds | executions | corpus | findings | slow inputs |"
  echo "| --- | ---: | ---: | ---: | ---: | ---: |"
}

# fuzz_one BUILD SECONDS TARGET: runs fuzz_TARGET (or $FUZZ_BIN with BOUGUER_FUZZ_TARGET=TARGET) for
# SECONDS on the committed corpus and BUILD/fuzz-corpus/TARGET, where new inputs collect; a crash,
# a timeout, a leak or an allocation past the limits leaves its input in BUILD/fuzz-findings/TARGET/.
# Prints the row of the summary table; fails when there is a finding. FUZZ_FLAGS adds options;
# FUZZ_TIMEOUT (default 10 s) is the time one input may take: raise it on a loaded machine, where
# the wall-clock time of a slow but finite input (a scene's albedo tables: 2 s of CPU) can pass 10 s.
fuzz_one() {
  local build=$1 seconds=$2 t=$3
  local work="$build/fuzz-corpus/$t" findings="$build/fuzz-findings/$t" log="$build/fuzz-$t.log"
  local dict="$build/fuzz-$t.dict" parts
  mkdir -p "$work" "$findings"
  # Keywords of the format (tests/fuzz/dict), shared between targets of one format.
  case "$t" in
    ply_*) parts=(ply) ;; spectrum_csv) parts=(csv) ;; material_csv) parts=(csv material_csv) ;;
    environment) parts=(exr pfm) ;; *) parts=("$t") ;;
  esac
  : >"$dict"
  for p in "${parts[@]}"; do cat "tests/fuzz/dict/$p.dict" >>"$dict"; done
  local before start rc
  # Findings: crashes, leaks, timeouts, allocations past the limits. Slow inputs (libFuzzer's
  # slow-unit-*, over -report_slow_units seconds of wall clock: on a loaded machine, ordinary
  # inputs) are counted apart, to be replayed.
  count() { find "$findings" -type f ! -name 'slow-unit-*' | wc -l; }
  slow_count() { find "$findings" -type f -name 'slow-unit-*' | wc -l; }
  before=$(count)
  local slow_before
  slow_before=$(slow_count)
  start=$(date +%s)
  set +e
  # shellcheck disable=SC2086
  BOUGUER_FUZZ_TARGET="$t" "${FUZZ_BIN:-$build/tests/fuzz/fuzz_$t}" "$work" "tests/fuzz/corpus/$t" -dict="$dict" \
    -max_total_time="$seconds" -timeout="${FUZZ_TIMEOUT:-10}" -rss_limit_mb=2048 -malloc_limit_mb=1024 -print_final_stats=1 \
    -artifact_prefix="$findings/" ${FUZZ_FLAGS:-} >"$log" 2>&1
  rc=$?
  set -e
  local took=$(( $(date +%s) - start ))
  local runs corpus found
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  corpus=$(grep -o 'corp: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  found=$(( $(count) - before ))
  [ "$rc" -eq 0 ] || [ "$found" -gt 0 ] || found="exit $rc"
  echo "| $t | $took | ${runs:-?} | ${corpus:-?} | $found | $(( $(slow_count) - slow_before )) |"
  if [ "$rc" -ne 0 ]; then
    grep -m3 -E "ERROR|SUMMARY|Test unit written" "$log" >&2 || tail -5 "$log" >&2
    return 1
  fi
}
