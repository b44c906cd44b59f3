#!/usr/bin/env bash
# The Khronos glTF validator over every glTF asset the tests write and every asset under scenes/:
# scripts/validate-gltf.sh BUILD_DIR. Installs the validator (npm package gltf-validator) into
# BUILD_DIR/gltf-validator the first time. Exits 77 (ctest: skipped) where npm or the registry is not
# to be had, 1 when any asset has an error, 0 otherwise. Run by the ctest gltf_validator.
set -euo pipefail
build="$(cd "$1" && pwd)"
repo="$(cd "$(dirname "$0")/.." && pwd)"
tool="$build/gltf-validator"
if [ ! -d "$tool/node_modules/gltf-validator" ]; then
  command -v npm > /dev/null || { echo "skipped: npm is not installed"; exit 77; }
  mkdir -p "$tool"
  npm install --prefix "$tool" --no-audit --no-fund gltf-validator@2.0.0-dev.3.10 > "$tool/install.log" 2>&1 \
    || { echo "skipped: could not install gltf-validator (see $tool/install.log)"; exit 77; }
fi
scratch="$build/gltf-validation"
rm -rf "$scratch"
mkdir -p "$scratch"
# The assets the tests write, into a folder of their own (malformed ones on purpose are left out,
# and the tests of bad input, which write no valid asset: the same 36 assets in a third of the time).
BOUGUER_TEST_SCRATCH="$scratch" "$build/tests/bouguer_tests" \
  --gtest_filter='Gltf*:Texture*:*Textured*:Nested*:-*Bad*:*Malformed*:*Hostile*' \
  > "$scratch/tests.log" 2>&1 || { echo "the tests that write the assets failed:"; tail -20 "$scratch/tests.log"; exit 1; }
mapfile -t files < <(find "$scratch" "$repo/scenes" \( -name '*.glb' -o -name '*.gltf' \) ! -path '*bad*' ! -path '*malformed*' | sort)
[ "${#files[@]}" -gt 0 ] || { echo "no glTF assets found"; exit 1; }
NODE_PATH="$tool/node_modules" node "$repo/scripts/validate-gltf.js" "${files[@]}"
