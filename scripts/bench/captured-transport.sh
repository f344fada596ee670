#!/usr/bin/env bash
# A captured-like one-light-at-a-time set, imported and compressed, measured
# (docs/results.md, "Captured transport"): the plant's model relit under N
# small suns on a light-stage layout (a dome from the zenith to 30 degrees
# below the horizon), written as 8-bit sRGB PNGs with a CSV of directions and
# irradiances, then `import` (time, peak memory) and `compress --method
# adaptive-binary` (time), each beside the machine's streaming read.
#
#   bash scripts/bench/captured-transport.sh OUT_DIR [SIZE (1024)] [LIGHTS (331)]
#
# Needs about 2 GiB of free disk in OUT_DIR at 1024x1024 and 331 lights.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1 size=${2:-1024} lights=${3:-331}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
mkdir -p "$out"
model=$out/plant$size-model.h5
[ -f "$model" ] || "$cli" build --scene plant --size ${size}x$size --method adaptive-binary \
  --quiet --out "$model"
# The suns: 2 degrees across, of irradiance pi at normal incidence (a white
# Lambertian surface facing one shows 1), on a golden spiral over the dome.
/usr/bin/python3 - "$out" "$lights" <<'PY'
import math, sys
out, n = sys.argv[1], int(sys.argv[2])
disc = 2 * math.pi * (1 - math.cos(math.radians(1.0)))
with open(f"{out}/suns.txt", "w") as suns, open(f"{out}/directions.csv", "w") as dirs:
    for i in range(n):
        y = 1 - 1.5 * (i + 0.5) / n
        r = math.sqrt(1 - y * y)
        a = math.pi * (3 - math.sqrt(5)) * i
        x, z = r * math.cos(a), r * math.sin(a)
        theta, phi = math.degrees(math.acos(y)), math.degrees(math.atan2(x, -z))
        suns.write(f"sun:{theta:.6f},{phi:.6f},2,{math.pi / disc:.6f}\n")
        dirs.write(f"{x!r},{y!r},{z!r}\n")
PY
mapfile -t suns <"$out/suns.txt"
envs=()
for s in "${suns[@]}"; do envs+=(--env "$s"); done
rm -rf "$out/olat"
"$cli" relight "$model" "${envs[@]}" --background black --format png --quiet --out "$out/olat"
# The CSV: each frame's image (manifest.jsonl, in sun order) and its light.
/usr/bin/python3 - "$out" <<'PY'
import json, math, os, sys
out = sys.argv[1]
frames = [json.loads(line) for line in open(f"{out}/olat/manifest.jsonl")]
directions = [line.strip() for line in open(f"{out}/directions.csv")]
with open(f"{out}/olat/lights.csv", "w") as f:
    f.write("image,x,y,z,r,g,b\n")
    for frame, d in zip(frames, directions):
        image = os.path.basename(frame["outputs"][0] if "outputs" in frame else frame["output"])
        f.write(f"{image},{d},{math.pi!r},{math.pi!r},{math.pi!r}\n")
PY
echo "machine: $(nproc) cores; streaming read and rays:"
"$cli" bench relight "$model" --quiet 2>/dev/null | grep -i "stream\|GB/s" | head -3 || true
"$cli" bench rays --scene plant --quiet 2>/dev/null | tail -2 || true
/usr/bin/time -v "$cli" import "$out/olat/lights.csv" --out "$out/olat.h5" --json "$out/import.json" \
  2>"$out/import.time"
grep -E "Elapsed|Maximum resident" "$out/import.time"
"$cli" info "$out/olat.h5"
/usr/bin/time -v "$cli" compress "$out/olat.h5" --method adaptive-binary --out "$out/olat-model.h5" \
  --json "$out/compress.json" 2>"$out/compress.time"
grep -E "Elapsed|Maximum resident" "$out/compress.time"
"$cli" info "$out/olat-model.h5"
