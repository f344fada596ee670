#!/usr/bin/env bash
# Local lights on the plant, measured (docs/results.md, "Local lights"): the
# dense local-light relight of the transport, and the model's at anchor
# spread 0 (exact) and the default, for a point lamp, a sphere lamp and eight
# lights, with each model image's relative L2 against the dense one, beside
# the model's sky relight; then a point lamp moving along a 30-frame path.
#
#   bash scripts/bench/local-lights.sh OUT_DIR [SIZE (default 1024)]
#
# Needs about 9 GiB of free disk in OUT_DIR at 1024x1024 (the transport).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1 size=${2:-1024}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
mkdir -p "$out"
cd "$out"
[ -f plant.h5 ] || "$cli" precompute --scene plant --size "${size}x${size}" --spp 1 --quiet --out plant.h5
[ -f model.h5 ] || "$cli" compress plant.h5 --method adaptive-quad --coeffs f16 --bases f16 \
  --quiet --out model.h5
sphere="--light sphere:1.2,2.6,1.4,0.15,300"
declare -A lights=(
  [point]="--light point:1.2,2.6,1.4,30"
  [sphere]="$sphere"
  [eight]="$sphere --light point:-1.5,2.2,1,20 --light point:0,3,0,30 --light point:2,1.5,-1,10
    --light spot:0,3.5,2,0,-1,-0.5,30,80 --light point:-2,2,-1.5,15
    --light sphere:-1.8,1.2,2.2,0.2,100 --light point:1.5,2.8,-0.5,25"
)
"$cli" relight model.h5 --env sky --frames 10 --quiet --exr-float --out sky.exr --json sky.json
for name in point sphere eight; do
  # shellcheck disable=SC2086
  "$cli" relight plant.h5 ${lights[$name]} --quiet --exr-float --out "$name-dense.exr" \
    --json "$name-dense.json"
  for spread in 0 0.5; do
    # shellcheck disable=SC2086
    "$cli" relight model.h5 ${lights[$name]} --anchor-spread "$spread" --quiet --exr-float \
      --out "$name-$spread.exr" --json "$name-$spread.json"
  done
done
# A lamp moving along a path, 30 frames 0.02 units apart (about what a drag
# in the viewer moves it per frame): frames after the first form only the
# columns of texels new to a cluster.
for k in $(seq 0 29); do
  echo "point:$(awk "BEGIN{print 1.2 - 0.02 * $k}"),2.6,1.4,30"
done >path.txt
"$cli" relight model.h5 --light-path path.txt --quiet --out path --json path.json
PYTHONPATH="$OLDPWD/build/python" /usr/bin/python3 - <<'PY'
import json
import numpy as np
import adaptive_cpca as ac
print("model sky: %.2f ms/frame" % json.load(open("sky.json"))["ms_per_frame_median"])
for name in ("point", "sphere", "eight"):
    dense = ac.read_image(f"{name}-dense.exr")
    seconds = json.load(open(f"{name}-dense.json"))["stages"]["local_lights"]["seconds"]
    print(f"{name}: dense {1e3 * seconds:.0f} ms")
    for spread in ("0", "0.5"):
        model = ac.read_image(f"{name}-{spread}.exr")
        seconds = json.load(open(f"{name}-{spread}.json"))["stages"]["local_lights"]["seconds"]
        error = np.linalg.norm(model - dense) / np.linalg.norm(dense)
        print(f"{name}: model, spread {spread}: {1e3 * seconds:.0f} ms, error {100 * error:.2f}%")
path = json.load(open("path.json"))["stages"]["local_lights"]["seconds"]
print(f"point lamp along a 30-frame path: {1e3 * path / 30:.1f} ms/frame (first frame included)")
PY
