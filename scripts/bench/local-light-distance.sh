#!/usr/bin/env bash
# The model's local-light error against distance (docs/results.md, "Local
# lights"): a sphere lamp moved out from the plant's centre along one
# direction, from 1.25 to 20 scene radii, its radiance growing as the
# distance squared so that the plant's irradiance stays about the same; per
# distance the relative L2 of the model's image against the dense relight of
# the transport, at anchor spread 0 (the model's compression alone) and the
# default, beside the model's error under `sky`.
#
#   bash scripts/bench/local-light-distance.sh OUT_DIR [SIZE (default 256)] [METHOD (adaptive-quad)]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1 size=${2:-256} method=${3:-adaptive-quad}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
mkdir -p "$out"
cd "$out"
[ -f plant.h5 ] || "$cli" precompute --scene plant --size "${size}x${size}" --spp 1 --quiet --out plant.h5
[ -f "$method.h5" ] || "$cli" compress plant.h5 --method "$method" --quiet --out "$method.h5"
"$cli" relight plant.h5 --env sky --quiet --exr-float --out sky-dense.exr
"$cli" relight "$method.h5" --env sky --quiet --exr-float --out sky-model.exr
# The plant's centre and radius: the sphere around the box of the positions
# of its pixels off the floor (the floor, 14 units wide, would be most of it).
read -r cx cy cz radius < <(/usr/bin/python3 -c '
import h5py, numpy as np
p = h5py.File("plant.h5", "r")["position"][()]
p = p[p[:, 1] > 0.02]
lo, hi = p.min(axis=0), p.max(axis=0)
print(*((lo + hi) / 2), np.linalg.norm(hi - lo) / 2)')
distances="1.25 1.5 2 3 5 10 20"
rm -f lamps.txt
for k in $distances; do
  spec=$(/usr/bin/python3 -c "
k, c, r = $k, ($cx, $cy, $cz), $radius
d = (0.5, 0.8, 0.6)  # up and towards the camera's side, as the 1024 benchmark's lamp
n = sum(v * v for v in d) ** 0.5
p = [c[i] + k * r * d[i] / n for i in range(3)]
print('sphere:%.6g,%.6g,%.6g,%.6g,%.6g' % (*p, 0.15 * r / 1.5, 300 * (k / 3) ** 2))")
  echo "$k $spec" >>lamps.txt
  "$cli" relight plant.h5 --light "$spec" --quiet --exr-float --out "dense-$k.exr"
  for spread in 0 0.5; do
    "$cli" relight "$method.h5" --light "$spec" --anchor-spread "$spread" --quiet --exr-float \
      --out "model-$k-$spread.exr"
  done
done
PYTHONPATH="$OLDPWD/build/python" /usr/bin/python3 - "$distances" <<'PY'
import sys
import numpy as np
import adaptive_cpca as ac

def error(a, b):
    a, b = ac.read_image(a), ac.read_image(b)
    return 100 * np.linalg.norm(a - b) / np.linalg.norm(b)

sky = error("sky-model.exr", "sky-dense.exr")
print(f"model error under sky: {sky:.2f}%")
print("scene radii | spread 0 (compression) | spread 0.5 (default) | above sky")
for k in sys.argv[1].split():
    exact, shared = (error(f"model-{k}-{s}.exr", f"dense-{k}.exr") for s in ("0", "0.5"))
    print(f"{k:>11} | {exact:.2f}% | {shared:.2f}% | {shared - sky:+.2f} pt")
PY
