#!/usr/bin/env bash
# docs/images/duck-lamp-sweep.png (docs/lighting.md, "Lamps"): the Collada
# duck of Debian's assimp-testmodels on a floor, 128x128, a point lamp swept
# past it in eight frames, relit from its adaptive-quad model at the default
# settings (adaptive-quad) through the lattice (top, --light-mode lattice) and exactly
# (bottom). Prints each mode's error against the dense relight of the same
# lamp (relative L2 over the eight frames), beside the model's error under
# the sky.
#
#   bash scripts/pictures/duck-lamp-sweep.sh [OUT_PNG (default docs/images/duck-lamp-sweep.png)]
set -euo pipefail
cd "$(dirname "$0")/../.."
png=${1:-docs/images/duck-lamp-sweep.png}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Cycles' duck scene, its camera stepped back to take the whole duck in.
python3 - "$work" <<'PY'
import json, sys
scene = json.load(open("data/scenes/cycles/duck-diffuse.json"))
scene["camera"].update({"eye": [0, 1.6, 6], "target": [0, 0.6, 0]})
json.dump(scene, open(sys.argv[1] + "/duck.json", "w"))
PY
"$cli" precompute --scene "$work/duck.json" --size 128x128 --quiet --out "$work/t.h5"
"$cli" compress "$work/t.h5" --method adaptive-quad --quiet --out "$work/m.h5"
sweep="--light point:-1.75:2:0.5,1.5,1.2,6 --background black --format exr,png --exr-float"
for mode in lattice exact; do
  for file in t m; do
    # shellcheck disable=SC2086
    "$cli" relight "$work/$file.h5" $sweep --light-mode "$mode" --quiet --out "$work/$mode-$file"
  done
done
for file in t m; do
  "$cli" relight "$work/$file.h5" --env sky --background black --exr-float --quiet \
    --out "$work/sky-$file.exr"
done
python3 - "$work" <<'PY'
import glob, os, sys
import numpy as np
import OpenImageIO as oiio
work = sys.argv[1]
def read(path):
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)
def error(model, dense):
    return np.sqrt(((model - dense) ** 2).sum() / (dense ** 2).sum())
for mode in ("lattice", "exact"):
    frames = sorted(glob.glob(f"{work}/{mode}-m/*.exr"))
    model = np.stack([read(f) for f in frames])
    dense = np.stack([read(f.replace(f"{mode}-m", f"{mode}-t")) for f in frames])
    print(f"{mode}: model against dense over {len(frames)} frames {100 * error(model, dense):.2f}%, "
          f"negative values {(model < 0).sum()}")
print(f"sky: model against dense {100 * error(read(work + '/sky-m.exr'), read(work + '/sky-t.exr')):.2f}%")
PY
oiiotool "$work"/lattice-m/*.png "$work"/exact-m/*.png --mosaic 8x2 -o "$png"
echo "wrote $png"
