#!/usr/bin/env bash
# docs/images/lamp-under-table.png (docs/lighting.md, "Lamps"): a point lamp
# under a table top, relit from one transport through the lattice (left,
# --light-mode lattice: the transport traced each direction to infinity, so
# the table beyond the lamp shadows the floor right under it) and exactly
# (right, the default: a shadow ray from each camera sample, stopped at the
# lamp).
#
#   bash scripts/pictures/lamp-under-table.sh [OUT_PNG (default docs/images/lamp-under-table.png)]
set -euo pipefail
cd "$(dirname "$0")/../.."
png=${1:-docs/images/lamp-under-table.png}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cli" precompute --scene data/scenes/lamp-under-table.json --quiet --out "$work/table.h5"
for mode in lattice exact; do
  "$cli" relight "$work/table.h5" --light point:0,0.45,0.3,2 --env constant:0.03 \
    --light-mode "$mode" --quiet --out "$work/$mode.png"
done
oiiotool "$work/lattice.png" "$work/exact.png" --mosaic 2x1 -o "$png"
echo "wrote $png"
