#!/usr/bin/env bash
# Interreflections on the plant, measured (docs/results.md, "Interreflections"):
# precompute time and rays for K = 0..3 bounces at 256x256 and 1024x1024
# (--spp 1), and at 256x256 the noise of the default 64 paths per sample
# against a reference with 16x the paths (python/benchmarks/indirect_noise.py).
#
#   bash scripts/bench/bounces.sh OUT_DIR [SIZES (default "256 1024")]
#
# Needs about 25 GiB of free disk in OUT_DIR for a 1024x1024 transport with
# bounces (R, G and B rows); each is deleted once measured.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1 sizes=${2:-256 1024}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
mkdir -p "$out"
csv=$out/precompute.csv
echo "size,bounces,indirect_samples,seconds,cache_seconds,occlusion_rays,path_rays,cache_points,cache_rays,channels,row_bytes,peak_memory_bytes" >"$csv"
for size in $sizes; do
  for k in 0 1 2 3; do
    t=$out/plant$size-k$k.h5
    "$cli" precompute --scene plant --size ${size}x$size --spp 1 --bounces $k --quiet \
      --out "$t" --json "$out/plant$size-k$k.json"
    python3 - "$out/plant$size-k$k.json" "$size" >>"$csv" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print(",".join(str(v) for v in [sys.argv[2], j["bounces"], j["indirect_samples"], j["seconds"],
      j["cache_seconds"], j["occlusion_rays"], j["path_rays"], j["cache_points"],
      j["cache_rays"], j["channels"], j["row_bytes"], j["peak_memory_bytes"]]))
PY
    [ "$size" = 256 ] || rm -f "$t"
  done
done
if [[ " $sizes " == *" 256 "* ]]; then
  for k in 1 2 3; do
    ref=$out/plant256-k$k-ref.h5
    "$cli" precompute --scene plant --size 256x256 --spp 1 --bounces $k --indirect-samples 1024 \
      --quiet --out "$ref" --json "$out/plant256-k$k-ref.json"
    PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/indirect_noise.py \
      "$out/plant256-k$k.h5" "$ref" --direct "$out/plant256-k0.h5" --json "$out/noise256-k$k.json"
    rm -f "$ref"
  done
fi
column -s, -t "$csv"
