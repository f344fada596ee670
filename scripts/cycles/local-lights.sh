#!/usr/bin/env bash
# Local lights against Cycles (docs/results.md, "Local lights"): a sphere lamp
# and a point lamp over one diffuse plane (also against the closed form: the
# lamp-strength conversion), over the textured Collada duck and the textured
# glTF box (each lit exactly, from the transport and from its model), direct
# light, and over the duck on a red floor with one bounce. Each lamp
# is outside the scene's geometry along every pixel's ray to it, where the
# dense relight is exact up to the lattice. Not part of CI: needs Debian's
# `blender` and a few minutes.
#
#   bash scripts/cycles/local-lights.sh OUT_DIR [compare.sh options, e.g. --samples 4096]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1
shift
compare() {  # NAME SCENE [options]
  local name=$1 scene=$2
  shift 2
  echo "== $name"
  bash scripts/cycles/compare.sh "data/scenes/cycles/$scene.json" none "$out/$name" "$@"
}
lamp=sphere:1.2,2.5,1.5,0.1,300
compare plane lamp-plane --camera none --light sphere:0.3,1.5,0.2,0.075,400 --closed-form "$@"
compare plane-point lamp-plane --camera none --light point:0.3,1.5,0.2,7 --closed-form "$@"
compare duck duck-diffuse --light "$lamp" --model "$@"
compare duck-point duck-diffuse --light point:1.2,2.5,1.5,9.4 --model "$@"
compare box box-gltf --light sphere:-1,2.2,1.2,0.08,400 --model "$@"
compare box-point box-gltf --light point:-1,2.2,1.2,8.0 --model "$@"
compare bounce-duck bounce-duck --light "$lamp" --bounces 1 "$@"
