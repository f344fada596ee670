#!/usr/bin/env bash
# The main job on built-in defaults: set up, build, precompute the built-in plant
# at 256x256 against the 6x32x32 lattice, relight it densely under built-in
# lightings and a yaw sweep, compress it (adaptive-quad) and relight the model.
# Results go to out/demo/ (override: OUT=dir).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh build
# The CLI alone (and the libraries it links): no test suites, no fixtures.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target adaptive-cpca
out="${OUT:-out/demo}"
mkdir -p "$out"
cli=build/tools/adaptive-cpca

$cli precompute --scene plant --out "$out/plant.h5"
$cli info "$out/plant.h5"
$cli relight "$out/plant.h5" --env sky --env sun:50,30,4,1000 --env sun:70,200,8,300 \
  --env constant:1 --format both --out "$out/images"
$cli relight "$out/plant.h5" --env sky --rotate 0:360:45 --format png --out "$out/sky-turn"
$cli compress "$out/plant.h5" --method adaptive-quad --out "$out/plant-model.h5"
$cli info "$out/plant-model.h5"
$cli relight "$out/plant-model.h5" --env sky --env sun:50,30,4,1000 --format png --out "$out/model-images"
# Timing mode: 50 frames of the fast relighter, ms/frame and GB/s.
$cli relight "$out/plant-model.h5" --env sky --frames 50 --out "$out/model-sky.png" \
  --json "$out/relight-timing.json"
$cli envmap sky --out "$out/sky-lattice.exr" --cross "$out/sky-cross.exr"
echo
echo "demo: transport in $out/plant.h5"
echo "demo: relit images (EXR + PNG) and manifest.csv in $out/images/"
echo "demo: the sky turned in 45-degree steps in $out/sky-turn/"
echo "demo: adaptive-quad model in $out/plant-model.h5, relit from it in $out/model-images/"
echo "demo: relighter timing (50 frames) in $out/relight-timing.json"
