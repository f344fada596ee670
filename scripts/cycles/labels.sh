#!/usr/bin/env bash
# Per-pixel labels against Blender Cycles' render passes (docs/datasets.md,
# "Checked against Cycles"): our normal, depth and albedo labels of a scene
# against Cycles' Normal, Depth and DiffCol passes of the same camera, as
# relative L2 over interior pixels (scripts/cycles/compare_labels.py says
# which). Not part of CI: needs Debian's `blender`.
#
#   bash scripts/cycles/labels.sh OUT_DIR [--samples N (Cycles, 256)] [--spp N (ours, 64)]
#     [--size WxH (160x120)]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1
shift
samples=256 spp=64 size=160x120
while [ $# -gt 0 ]; do
  case $1 in
    --samples) samples=$2 ;;
    --spp) spp=$2 ;;
    --size) size=$2 ;;
    *) echo "labels.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
command -v blender >/dev/null || { echo "labels.sh: needs blender (apt-get install blender)" >&2; exit 1; }
cli=build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
width=${size%x*} height=${size#*x}
for scene in label-sphere box-gltf duck-diffuse; do
  dir="$out/$scene"
  mkdir -p "$dir"
  json="data/scenes/cycles/$scene.json"
  # Every camera sample traced (--aa full), as Cycles integrates the whole pixel.
  "$cli" precompute --scene "$json" --size "$size" --spp "$spp" --aa full --cubemap 4 \
    --camera auto:65,150 --quiet --out "$dir/t.h5"
  "$cli" relight "$dir/t.h5" --env constant:1 --aov albedo,normal,depth,mask,object \
    --label-format npy --quiet --out "$dir/ours.exr"
  cam=$("$cli" info "$dir/t.h5" --json - | python3 -c '
import json, sys
c = json.load(sys.stdin)["camera"]
print(",".join(repr(float(v)) for v in c["eye"] + c["target"] + c["up"] + [c["fov"]]))')
  blender -b --factory-startup --python-exit-code 1 --python scripts/cycles/render_cycles.py -- \
    --scene "$json" --width "$width" --height "$height" --camera "$cam" --env none \
    --samples "$samples" --seed 1 --passes --out "$dir/cycles.exr" >"$dir/blender.log" 2>&1 ||
    { tail -30 "$dir/blender.log" >&2; exit 1; }
  echo "== $scene"
  PYTHONPATH=build/python /usr/bin/python3 scripts/cycles/compare_labels.py "$dir" "$cam" \
    | tee "$dir/comparison.txt"
done
