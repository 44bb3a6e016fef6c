#!/usr/bin/env bash
# The wheel's build re-uses the test step's compilation only while every
# crate the bindings use has the features the workspace's test build gives
# it (see python/Cargo.toml). This lists any crate whose features differ and
# fails, naming what python/Cargo.toml must add.
set -euo pipefail
cd "$(dirname "$0")/.."
tree() { cargo tree --locked "$@" -f '{p}|{f}' --prefix none | sed 's/ (\*)$//' | sort -u; }
ws=$(tree --workspace -e normal,build,dev)
py=$(tree -p natura-python -e normal,build)
diff=$(comm -13 <(echo "$ws") <(echo "$py"))
if [ -n "$diff" ]; then
  echo "FAIL: natura-python builds these crates with other features than the test step:" >&2
  while IFS='|' read -r pkg features; do
    want=$(echo "$ws" | grep -F "$pkg|" | cut -d'|' -f2 | paste -sd' ')
    echo "  $pkg: [$features], the test step: [$want]" >&2
  done <<< "$diff"
  echo "add the test step's features to python/Cargo.toml" >&2
  exit 1
fi
echo "natura-python's crates have the test step's features ($(echo "$py" | wc -l) crates)"
