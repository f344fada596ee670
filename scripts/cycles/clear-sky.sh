#!/usr/bin/env bash
# Writes the clear-day sky of the map-sun checks (scripts/cycles/map-sun.sh,
# scripts/pictures/map-sun-cycles.sh): 2048x1024, from (0.02, 0.04, 0.11) at
# the zenith to (0.13, 0.19, 0.30) at the horizon, a ground of (0.06, 0.05,
# 0.045), and a 3x3-pixel (0.53-degree) sun of radiance (70000, 67700, 63000)
# at THETA 50, PHI 30 holding about 79% of the light.
#
#   bash scripts/cycles/clear-sky.sh OUT.exr
set -euo pipefail
oiiotool --pattern fill:top=0.02,0.04,0.11:bottom=0.13,0.19,0.3 2048x512 3 \
  --pattern constant:color=0.06,0.05,0.045 2048x512 3 --mosaic 1x2 \
  --box:color=70000,67700,63000:fill=1 1194,283,1196,285 -d float -o "$1"
