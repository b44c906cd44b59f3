#!/usr/bin/env bash
# make demo: what Bouguer can show today. Prints the colour of each standard illuminant.
set -euo pipefail
build=${1:-build}
for illuminant in D65 D50 A E F2 F7 F11 blackbody:3200K; do
  "$build/bouguer" color "$illuminant"
done
