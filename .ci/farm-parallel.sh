#!/usr/bin/env bash
# The zero-infrastructure farm: GNU parallel runs every tile of every frame
# of the tiny scene (3 frames × 6 tiles, 2 at a time), `natura assemble`
# checks and joins them, and the frames must equal single-process renders.
set -euo pipefail
if ! command -v parallel >/dev/null; then
  echo "FAIL: GNU parallel not found (apt-get install parallel; .ci/run installs it)" >&2; exit 1
fi
source "$(dirname "$0")/farm-common.sh"
out="target/ci-farm/parallel"
rm -rf "$out"
"$natura" prepare "$scene" --out "$out"
parallel --will-cite --halt now,fail=1 -j 2 \
  "$natura" render "$scene" --frame {1} --tile {2}/6 --out "$out" ">/dev/null" \
  ::: 0 1 2 ::: $(seq 0 5)
"$natura" assemble "$out"
same_as_single_process "$out" 0 1 2
