#!/usr/bin/env bash
# docs/images/brushed-disc.png (docs/scenes.md, "Tangents"): the brushed
# disc of the Cycles check (data/scenes/cycles/brushed.json: anisotropic GGX,
# roughness 0.12, anisotropy 0.8, tangent +X) seen from straight above,
# under a map holding a 1-degree sun 30 degrees from the zenith, at yaw 0,
# 45 and 90 degrees, from one transport. Below, the same disc made isotropic
# (roughness 0.12, no anisotropy): its highlight is a spot where the brushed
# one is drawn out along the tangent, whichever side the sun comes from.
#
#   bash scripts/pictures/brushed-disc.sh [OUT_PNG (default docs/images/brushed-disc.png)]
set -euo pipefail
cd "$(dirname "$0")/../.."
png=${1:-docs/images/brushed-disc.png}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - data/scenes/cycles/brushed.json "$work" <<'PY'
import json, os, sys
scene = json.load(open(sys.argv[1]))
scene["objects"][0]["mesh"] = os.path.abspath("data/meshes/disc.obj")
scene["camera"] = {"eye": [0, 1.25, 0.01], "target": [0, 0, 0], "up": [0, 0, -1], "fov": 80}
json.dump(scene, open(f"{sys.argv[2]}/brushed.json", "w"))
for o in scene["objects"]:
    o["material"].pop("anisotropy", None)
    o["material"].pop("rotation", None)
json.dump(scene, open(f"{sys.argv[2]}/round.json", "w"))
PY
tiles=()
for name in brushed round; do
  "$cli" precompute --scene "$work/$name.json" --size 288x192 --spp 4 --aa full --quiet \
    --out "$work/$name.h5"
  for yaw in 0 45 90; do
    "$cli" relight "$work/$name.h5" --env sun:30,0,1,3000 --rotate "$yaw" --exposure -4 \
      --background black --quiet --out "$work/$name-$yaw.png"
    tiles+=("$work/$name-$yaw.png")
  done
done
oiiotool "${tiles[@]}" --mosaic 3x2 -o "$png"
echo "wrote $png"
