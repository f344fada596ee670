#!/usr/bin/env bash
# A map's sun against Cycles (docs/results.md, "A map's sun against Cycles"):
# a clear-day sky, a 0.53-degree sun holding about 79% of its light, over a
# mesh on a plane (sun-check) and a GGX duck on a plane (duck-ggx). For each,
# compare.sh --sun auto: Cycles renders the sky less its sun as the world and
# the sun as a Sun lamp of the same angle and irradiance; ours lights it
# exactly, and the whole map on the lattice (`--sun off`) is printed beside.
# Not part of CI: needs Debian's `blender`; about 15 minutes on 2 cores at
# 4,096 samples.
#
#   bash scripts/cycles/map-sun.sh OUT_DIR [--samples N (4096)] [compare.sh options]
#
# The sky: scripts/cycles/clear-sky.sh.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1
shift
samples=4096
if [ "${1:-}" = --samples ]; then samples=$2; shift 2; fi
mkdir -p "$out"
bash scripts/cycles/clear-sky.sh "$out/clear-sky.exr"
for scene in sun-check duck-ggx; do
  echo "== $scene"
  bash scripts/cycles/compare.sh "data/scenes/cycles/$scene.json" "$out/clear-sky.exr" \
    "$out/$scene" --samples "$samples" "$@"
done
# ours (default --spp 16 --aa full) and the lattice against Cycles: relative
# L2 over covered pixels, within 2 px of the sun's shadow edges, and energy.
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
share = json.load(open(f"{out}/sun-check/sources.json"))["sources"][0]["energy_share"]
print(f"the sun: {100 * share:.1f}% of the sky's light")
print("scene      frame    covered  shadow edges  energy    Cycles vs Cycles: covered, edges")
for scene in ("sun-check", "duck-ggx"):
    r = json.load(open(f"{out}/{scene}/comparison.json"))
    ours, noise, edges = r["ours_vs_cycles"], r["cycles_seed_1_vs_2"], r["shadow_edges"]
    for name, c, e in (("exact", ours, edges["ours"]),
                       ("lattice", ours["also"]["lattice"], edges["lattice"])):
        print(f"{scene:10s} {name:8s} {100 * c['relative_l2']:6.2f}%  {100 * e:8.2f}%  "
              f"{c['energy_ratio']:9.4f}   {100 * noise['relative_l2']:.2f}%, "
              f"{100 * edges['cycles_seed_2']:.2f}%")
PY
