#!/usr/bin/env bash
# docs/images/lamp-under-table.png (docs/lighting.md, "When the result is
# exact"): a lamp under a table top, relit from the transport (left), beside
# the same lamp over the floor alone (right), which is the floor's exact
# direct light: no segment from the floor up to the lamp reaches the table.
# The transport traced each direction to infinity, so the table beyond the
# lamp shadows the floor right under it.
#
#   bash scripts/pictures/lamp-under-table.sh [OUT_PNG (default docs/images/lamp-under-table.png)]
set -euo pipefail
cd "$(dirname "$0")/../.."
png=${1:-docs/images/lamp-under-table.png}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - "$work" <<'PY'
import json, sys
scene = json.load(open("data/scenes/lamp-under-table.json"))
scene["name"], scene["objects"] = "lamp-floor-only", scene["objects"][:1]
json.dump(scene, open(sys.argv[1] + "/floor.json", "w"))
PY
lamp="--light point:0,0.45,0.3,2 --env constant:0.03"
for name in table floor; do
  scene=data/scenes/lamp-under-table.json
  [ "$name" = floor ] && scene=$work/floor.json
  "$cli" precompute --scene "$scene" --quiet --out "$work/$name.h5"
  # shellcheck disable=SC2086
  "$cli" relight "$work/$name.h5" $lamp --quiet --out "$work/$name.png"
done
oiiotool "$work/table.png" "$work/floor.png" --mosaic 2x1 -o "$png"
echo "wrote $png"
