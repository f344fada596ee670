#!/usr/bin/env bash
# docs/images/map-sun-cycles.png and map-sun-sweep.png (docs/lighting.md,
# "A map's sources"; README): the sun-check scene (a mesh on a plane) under
# the clear-day sky of scripts/cycles/clear-sky.sh, 320x240, by
# scripts/cycles/compare.sh --sun auto (ours --aa full --spp 16; Cycles 1,024
# samples). Top: the sun on the lattice (--sun off), lit exactly (the
# default), and Cycles (the sky less its sun as the world, the sun a Sun lamp
# of its angle and irradiance). Below: the shadow's tip in each enlarged 5x.
# The sweep: the exact sun's frames at --rotate 0:360:45, one strip.
# Needs Debian's `blender` (a few minutes on 2 cores).
#
#   bash scripts/pictures/map-sun-cycles.sh [OUT_DIR (default docs/images)]
set -euo pipefail
cd "$(dirname "$0")/../.."
images=${1:-docs/images}
mkdir -p "$images"
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bash scripts/cycles/clear-sky.sh "$work/sky.exr"
bash scripts/cycles/compare.sh data/scenes/cycles/sun-check.json "$work/sky.exr" "$work/c" \
  --size 320x240 --samples 1024 >"$work/compare.log"
tone() {  # linear EXR -> 8-bit sRGB, one exposure for every panel
  oiiotool "$1" --ch R,G,B --mulc 0.35 --colorconvert linear sRGB -d uint8 -o "$2"
}
panels=()
for name in lattice-sun ours cycles; do
  tone "$work/c/$name.exr" "$work/$name.png"
  oiiotool "$work/$name.png" --cut 64x48+125+180 --resize:filter=box 320x240 \
    -o "$work/${name}_edge.png"
  panels+=("$work/$name.png")
done
oiiotool "${panels[@]}" "$work/lattice-sun_edge.png" "$work/ours_edge.png" \
  "$work/cycles_edge.png" --mosaic:pad=4 3x2 -o "$images/map-sun-cycles.png"
"$cli" relight "$work/c/t.h5" --env "$work/sky.exr" --rotate 0:360:45 --background black \
  --exr-float --format exr --quiet --out "$work/sweep"
frames=()
for f in "$work"/sweep/*.exr; do
  tone "$f" "${f%.exr}.png"
  frames+=("${f%.exr}.png")
done
oiiotool "${frames[@]}" --mosaic:pad=2 "${#frames[@]}x1" --resize 50% \
  -o "$images/map-sun-sweep.png"
grep -E "relative L2|shadow edges" "$work/compare.log"
echo "wrote $images/map-sun-cycles.png and $images/map-sun-sweep.png"
