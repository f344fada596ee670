#!/usr/bin/env bash
# Lamps lit exactly, measured (docs/results.md, "Point and spot lamps,
# exact" and "Sphere lamps, exact"): a lamp frame of the plant's default
# model (adaptive-quad) against a sky frame of it and the bound the lamps'
# issue set, a sky frame plus 1.3 x covered pixels / the machine's
# shadow-ray rate (`bench rays`), beside the lattice path; a sphere lamp at
# 16 and 64 penumbra rays with the shadow rays per covered pixel; with the
# machine's streaming read.
#
#   bash scripts/bench/exact-lamps.sh OUT_DIR [SIZE (default 1024)]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1 size=${2:-1024}
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
mkdir -p "$out"
cd "$out"
[ -f model.h5 ] || "$cli" build --scene plant --size "${size}x${size}" --quiet --out model.h5
"$cli" bench rays --scene plant --rows 16 >rays.txt
"$cli" bench relight model.h5 --frames 10 >relight.txt
rm -rf sky lamp-exact lamp-lattice
"$cli" relight model.h5 --env sky --rotate 0:360:45 --background black --quiet --json sky.json \
  --out sky
for mode in exact lattice; do
  "$cli" relight model.h5 --light point:-1:1:0.0625,2.6,1.4,100 --light-mode "$mode" \
    --background black --quiet --json "lamp-$mode.json" --out "lamp-$mode"
done
# A sphere lamp of the same centre (eight frames), at 16 and 64 penumbra rays.
rm -rf sphere-16 sphere-64
for rays in 16 64; do
  "$cli" relight model.h5 --light sphere:-1:1:0.25,2.6,1.4,0.15,300 --lamp-rays "$rays" \
    --background black --quiet --json "sphere-$rays.json" --out "sphere-$rays"
done
"$cli" info model.h5 --json info.json >/dev/null
/usr/bin/python3 - <<'PY'
import json, re
rays = float(re.search(r"precompute \(4x4 texel blocks[^\n]*?\s([\d.]+)\s+[\d.]+\n",
                       open("rays.txt").read()).group(1))
stream = re.search(r"streaming read[^\n]*", open("relight.txt").read()).group(0)
covered = json.load(open("info.json"))["occupied_pixels"]
sky = json.load(open("sky.json"))["ms_per_frame_median"]
print(stream)
print(f"bench rays: {rays:.1f} M rays/s; covered pixels {covered}")
print(f"sky, batch of 8: {sky:.1f} ms/frame")
for mode in ("exact", "lattice"):
    stage = json.load(open(f"lamp-{mode}.json"))["stages"]["local_lights"]
    print(f"point lamp, {mode}: {stage['ms_per_frame']:.1f} ms/frame over 32 frames")
print(f"bound: {sky:.1f} + 1.3 x {covered} / {rays:.1f} M = "
      f"{sky + 1.3 * covered / (rays * 1e3):.1f} ms")
for n in (16, 64):
    j = json.load(open(f"sphere-{n}.json"))
    ms = j["stages"]["local_lights"]["ms_per_frame"]
    print(f"sphere lamp, {n} penumbra rays: {ms:.1f} ms/frame ({ms / sky:.1f}x sky), "
          f"{j['lamp_shadow_rays']['per_covered_pixel']:.2f} shadow rays per covered pixel")
PY
