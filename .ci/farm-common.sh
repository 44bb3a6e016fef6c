# Shared by the farm checks: the release `natura` binary, the tiny scene, and
# a comparison of assembled frames with single-process renders.
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export CARGO_TERM_COLOR=never
scene="${NATURA_FARM_SCENE:-tests/data/farm_tiny.toml}"
# --workspace with the examples: the features of the README's test command,
# so after it nothing is compiled again (the binary alone resolves its
# dependencies' features differently and would rebuild every crate).
cargo build --workspace --release --quiet --bins --examples
natura="${CARGO_TARGET_DIR:-$PWD/target}/release/natura"

# same_as_single_process OUT FRAME...: every assembled frame's EXR and PNG
# equal, byte for byte, the frame rendered whole by one process.
same_as_single_process() {
  local out="$1"; shift
  local ref="$out/single-process"
  for f in "$@"; do
    "$natura" render "$scene" --frame "$f" --out "$ref" >/dev/null
    for ext in exr png; do
      local name; name="$(printf 'frame_%04d.%s' "$f" "$ext")"
      if ! cmp -s "$out/$name" "$ref/$name"; then
        echo "FAIL: $out/$name differs from the single-process render" >&2
        exit 1
      fi
      sha256sum "$out/$name" | sed 's/^/  /'
    done
  done
  echo "assembled frames equal the single-process renders (SHA-256 above)"
}
