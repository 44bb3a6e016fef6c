#!/usr/bin/env bash
# natura's Open Job Description template run by the reference OpenJD tool
# (PyPI package openjd-cli): `openjd check` validates the template, then
# `openjd run` runs Prepare, Render (2 frames × 4 tiles) and Assemble
# locally, and the frames must equal single-process renders.
set -euo pipefail
if ! command -v openjd >/dev/null; then
  echo "FAIL: openjd not found (pip install openjd-cli; .ci/run installs it)" >&2; exit 1
fi
source "$(dirname "$0")/farm-common.sh"
out="$PWD/target/ci-farm/openjd"
rm -rf "$out"
"$natura" farm openjd "$scene" --out "$out" --tiles 4 --frames 0-1
openjd check "$out/natura.openjd.yaml"
openjd run "$out/natura.openjd.yaml" -p Scene="$PWD/$scene" --step Assemble --run-dependencies >"$out.log" 2>&1 \
  || { tail -n 40 "$out.log"; exit 1; }
grep -E "Session ended|succeeded|FAILED" "$out.log" | tail -n 3 || true
same_as_single_process "$out" 0 1
