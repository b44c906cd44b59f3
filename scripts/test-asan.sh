#!/usr/bin/env bash
# make test-asan: the whole test suite built with AddressSanitizer and UBSan (gcc, RelWithDebInfo
# at -O1, frame pointers kept) in BUILD, run by ctest without the tests labelled `long`. Any ASan
# or UBSan report fails its test (UBSan halts on the first error; leaks are reported, minus
# tests/lsan.supp's libraries that are not ours). The Python module and the MPI module are left out:
# Python would need the ASan runtime preloaded, and Open MPI's own leaks drown the report.
#   scripts/test-asan.sh [BUILD]     (default build-asan)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-asan}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}
bash scripts/install-deps.sh
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" \
  "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g" -DBOUGUER_SANITIZE=ON -DBOUGUER_BUILD_BENCH=OFF -DBOUGUER_PYTHON=OFF \
  -DBOUGUER_MPI=OFF >/dev/null
cmake --build "$build" -j "$jobs"
# intercept_tls_get_addr=0: GCC 12's sanitizer runtime (up to GCC 13 and LLVM 16) reads a dynamic
# TLS block whose address happens to sit 16 bytes into a page as one with glibc 2.19's header, and
# LeakSanitizer's tracer then crashes at exit ("Tracer caught signal 11"). Reading a bad PNG in a
# glTF through the texture module (OpenImageIO, dlopen'd) triggered it every time in
# TextureChannels.BadGltfTexturesAreOneLine; the same workaround as Mudlet's (Mudlet/Mudlet#9930).
# Its cost: LeakSanitizer no longer scans dynamic TLS, so memory held only by a dlopen'd library's
# thread_local would be reported as a leak (none is).
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:intercept_tls_get_addr=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
ctest --test-dir "$build" --output-on-failure -j "$jobs" -LE long
