#!/usr/bin/env bash
# docs/images/map-sun.png (docs/lighting.md, "A map's sources"): the example
# scene under a lat-long sky holding a 0.53-degree sun (a 3x3-pixel disc of
# radiance 4e4 on a 2048x1024 map, THETA 50, PHI 30), relit from one
# transport with the sun on the lattice (left, --sun off: spread over a
# 2.8-degree texel and moved to its centre) and split off and lit exactly
# (right, the default). Below, the same shadow edge of each enlarged 4x:
# the lattice draws it about a pixel off.
#
#   bash scripts/pictures/map-sun.sh [OUT_PNG (default docs/images/map-sun.png)]
set -euo pipefail
cd "$(dirname "$0")/../.."
png=${1:-docs/images/map-sun.png}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
oiiotool --pattern constant:color=0.05,0.08,0.16 2048x1024 3 \
  --box:color=40000,40000,40000:fill=1 1194,283,1196,285 -d float -o "$work/sky.exr"
"$cli" precompute --scene data/scenes/example.json --size 384x256 --spp 4 --aa full \
  --quiet --out "$work/t.h5"
for sun in off auto; do
  "$cli" relight "$work/t.h5" --env "$work/sky.exr" --sun "$sun" --exposure -1 \
    --background black --quiet --out "$work/$sun.png"
  oiiotool "$work/$sun.png" --cut 96x64+150+175 --resize:filter=box 384x256 \
    -o "$work/${sun}_edge.png"
done
oiiotool "$work/off.png" "$work/auto.png" "$work/off_edge.png" "$work/auto_edge.png" \
  --mosaic 2x2 -o "$png"
echo "wrote $png"
