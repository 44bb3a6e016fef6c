#!/usr/bin/env bash
# The overhead of sharding: one frame rendered as 16 tiles, one process per
# tile, against the same frame as 1 tile, caches warm, one thread each.
# Prints the CPU time (user + system, which load on other cores disturbs
# less than wall time) of each and the ratio sum(16 tiles) / (1 tile).
# Not run by CI (about a minute on the benchmark scene).
set -euo pipefail
export NATURA_FARM_SCENE="${NATURA_FARM_SCENE:-tests/data/farm_bench.toml}"
source "$(dirname "$0")/farm-common.sh"
out="target/ci-farm/overhead"
rm -rf "$out"
export RAYON_NUM_THREADS=1
"$natura" prepare "$scene" --out "$out" >/dev/null
cpu() { # seconds of user + system time of the command
  local t; t=$( { TIMEFORMAT='%U %S'; time "$@" >/dev/null; } 2>&1 )
  echo "$t" | awk '{ printf "%.3f", $1 + $2 }'
}
"$natura" render "$scene" --tile 0/1 --out "$out/warm" --cache "$out/cache" >/dev/null
one=$(cpu "$natura" render "$scene" --tile 0/1 --out "$out/one" --cache "$out/cache")
sum=0
for i in $(seq 0 15); do
  t=$(cpu "$natura" render "$scene" --tile "$i/16" --out "$out/sixteen" --cache "$out/cache")
  sum=$(echo "$sum + $t" | bc -l)
done
"$natura" assemble "$out/sixteen" >/dev/null
"$natura" assemble "$out/one" >/dev/null
cmp "$out/one/frame_0000.exr" "$out/sixteen/frame_0000.exr"
printf '1 tile: %.2f CPU-s; 16 tiles: %.2f CPU-s in all; ratio %.3f (frames identical)\n' \
  "$one" "$sum" "$(echo "$sum / $one" | bc -l)"
