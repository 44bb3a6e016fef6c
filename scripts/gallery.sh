#!/usr/bin/env bash
# Regenerates docs/gallery: runs every example with the flags its pictures
# were made with and writes them where the README and the gallery pages
# link them.
#
#   scripts/gallery.sh                  # every picture, full size (about an hour on 2 cores)
#   scripts/gallery.sh landscape ocean  # only these examples
#   scripts/gallery.sh --quick --out target/gallery-quick   # small, into another folder (CI)
#
# Examples write their pictures into ./<example>/ by default; here each one
# gets the gallery folder of its area as --out. Variants that share a file
# name (the landscape's close-ups, the planet seen from the ground) are
# rendered into a staging folder and moved to their gallery name. Every
# example is listed here, or under "not in the gallery" with the reason,
# and the script refuses to run when one is missing from both.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'
}

quick=()
out="docs/gallery"
only=()
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=(--quick); shift ;;
    --out)
      [ $# -ge 2 ] || { echo "error: --out needs a directory" >&2; exit 2; }
      out="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "error: unknown flag $1 (try --help)" >&2; exit 2 ;;
    *) only+=("$1"); shift ;;
  esac
done

# Every example and the gallery folder of its area.
declare -A area=(
  [landscape]=render [panorama]=render
  [heightmap]=. [noise_gallery]=noise [erosion]=terrain
  [trace_heightmap]=trace [trace_panorama]=trace
  [sky]=atmos [rainbow]=atmos [mirage]=atmos
  [ocean]=ocean
  [figures_ffc]=figures [figures_tessendorf]=figures [figures_musgrave]=figures [figures_fedkiw]=figures [figures_foster]=figures [figures_stam]=figures [figures_mech]=figures [figures_deussen]=figures [figures_ebert]=figures [figures_fowler]=figures
  [smoke2d]=fluid [smoke3d]=fluid [liquid2d]=fluid
  [planet]=texture [planets]=texture [textures]=texture/textures
  [clouds]=volume [cloudscape]=volume [steam]=volume
  [plants]=plant [plant_models]=plant [forest]=plant
)
# Not in the gallery, and why.
declare -A skipped=(
  [lsystem]="draws the L-system file it is given; its pictures are the user's"
)

for src in examples/*.rs; do
  name="$(basename "$src" .rs)"
  if [ -z "${area[$name]+x}" ] && [ -z "${skipped[$name]+x}" ]; then
    echo "error: examples/$name.rs is neither in the gallery table nor listed as skipped" >&2
    exit 1
  fi
done
for name in "${only[@]}"; do
  if [ -z "${area[$name]+x}" ]; then
    echo "error: $name is not an example with gallery pictures (${!area[*]})" >&2
    exit 2
  fi
done

wanted() {
  [ ${#only[@]} -eq 0 ] && return 0
  local n
  for n in "${only[@]}"; do [ "$n" = "$1" ] && return 0; done
  return 1
}

stage="target/gallery-stage"
run() { # example, then its flags
  local name="$1"; shift
  printf '\n==> %s %s\n' "$name" "$*"
  "$bin/$name" "${quick[@]}" "$@"
}
# example, picture it writes, gallery name, then its flags
variant() {
  local name="$1" file="$2" as="$3"; shift 3
  local dir="$stage/$as"
  rm -rf "$dir"
  run "$name" --out "$dir" "$@"
  mkdir -p "$out/${area[$name]}"
  mv "$dir/$file" "$out/${area[$name]}/$as"
  rm -rf "$dir"
}

# Built with --workspace: the features of the README's test command, so
# after `cargo test --workspace --release` nothing is compiled again (built
# alone, the root package resolves its dependencies' features differently).
cargo build --quiet --locked --workspace --release --examples
bin="${CARGO_TARGET_DIR:-target}/release/examples"
for name in $(printf '%s\n' "${!area[@]}" | sort); do
  wanted "$name" || continue
  case "$name" in
    landscape)
      # The README shows the built-in scene at 1280×720.
      run landscape --out "$out/render" --width 1280 --height 720
      variant landscape landscape.png valley_morning.png \
        --scene examples/scenes/valley_morning.toml --width 960 --height 540
      # The close-ups show the ground whose detail they are for: without
      # the forest, a tree fills most of the frame.
      variant landscape landscape.png landscape_detail_off.png \
        --closeup --no-forest --no-detail --width 400 --height 225 --spp 8
      variant landscape landscape.png landscape_detail.png \
        --closeup --no-forest --width 400 --height 225 --spp 8
      ;;
    planet)
      run planet --out "$out/texture"
      run planet --out "$out/texture" --view ground
      ;;
    *)
      run "$name" --out "$out/${area[$name]}"
      ;;
  esac
done
printf '\nthe gallery is in %s\n' "$out"
