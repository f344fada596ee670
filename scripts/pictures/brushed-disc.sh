#!/usr/bin/env bash
# docs/images/brushed-disc.png (docs/scenes.md, "Tangents"): the brushed
# disc of the Cycles check (data/scenes/cycles/brushed.json: anisotropic GGX,
# anisotropy 0.8, tangent +X; beside it a sphere of the same lobe turned 30
# degrees) under Blender's courtyard HDRI at yaw 0, 60 and 120 degrees, from
# one transport. Below, the same disc made isotropic (roughness 0.25, no
# anisotropy): its highlight is round where the brushed one is stretched
# across the tangent and turns with the map.
#
#   bash scripts/pictures/brushed-disc.sh [OUT_PNG (default docs/images/brushed-disc.png)]
set -euo pipefail
cd "$(dirname "$0")/../.."
png=${1:-docs/images/brushed-disc.png}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
map=/usr/share/blender/datafiles/studiolights/world/courtyard.exr
[ -f "$map" ] || { echo "brushed-disc.sh: needs Debian's blender-data ($map)" >&2; exit 1; }
sed -e 's/, *"anisotropy": 0.8//g' -e 's/, "rotation": 30//' \
  -e 's|\.\./\.\./meshes|'"$PWD"'/data/meshes|' data/scenes/cycles/brushed.json >"$work/round.json"
tiles=()
for scene in data/scenes/cycles/brushed.json "$work/round.json"; do
  name=$(basename "$scene" .json)
  "$cli" precompute --scene "$scene" --size 288x192 --spp 4 --aa full --quiet --out "$work/$name.h5"
  for yaw in 0 60 120; do
    "$cli" relight "$work/$name.h5" --env "$map" --rotate "$yaw" --background black --quiet \
      --out "$work/$name-$yaw.png"
    tiles+=("$work/$name-$yaw.png")
  done
done
oiiotool "${tiles[@]}" --mosaic 3x2 -o "$png"
echo "wrote $png"
