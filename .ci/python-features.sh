#!/usr/bin/env bash
# The wheel's build re-uses the test step's compilation only while every
# crate the bindings use has the features the workspace's test build gives
# it (see python/Cargo.toml). This lists any crate that natura's crates
# build on whose features differ in the wheel's build and fails, naming
# what python/Cargo.toml must add. (rust-numpy, the bindings and what only
# they use are compiled by the wheel's build alone: the test build leaves
# the bindings' `extension` feature off, and maturin's settings compile
# PyO3 again in any case.)
set -euo pipefail
cd "$(dirname "$0")/.."
tree() { cargo tree --locked "$@" -f '{p}|{f}' --prefix none | sed 's/ (\*)$//' | sort -u; }
ws=$(tree --workspace -e normal,build,dev)
py=$(tree -p natura-python --features extension -e normal,build)
# The crates (name and version) the test build compiles for natura's
# crates: the ones the wheel must re-use.
ws_pkgs=$(tree --workspace --exclude natura-python -e normal,build,dev | cut -d'|' -f1 | sort -u)
diff=$(comm -13 <(echo "$ws") <(echo "$py") | while IFS='|' read -r pkg features; do
  if grep -qxF "$pkg" <<< "$ws_pkgs"; then echo "$pkg|$features"; fi
done)
if [ -n "$diff" ]; then
  echo "FAIL: natura-python builds these crates with other features than the test step:" >&2
  while IFS='|' read -r pkg features; do
    want=$(echo "$ws" | grep -F "$pkg|" | cut -d'|' -f2 | paste -sd' ')
    echo "  $pkg: [$features], the test step: [$want]" >&2
  done <<< "$diff"
  echo "add the test step's features to python/Cargo.toml" >&2
  exit 1
fi
shared=$(echo "$py" | cut -d'|' -f1 | grep -cxF -f <(echo "$ws_pkgs") || true)
echo "natura-python's crates have the test step's features ($shared shared crates)"
