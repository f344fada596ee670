"""Cycles' side of the captured-transport check (scripts/cycles/olat.sh):
renders a scene's one-light-at-a-time set under distant lamps, the same
scene under a set of distant lamps of given irradiances, or under a whole
environment map, direct light only. olat.sh compares the images.

Run inside Blender:
  blender -b --factory-startup --python render_olat.py -- --scene S.json \\
      --width W --height H --samples N --seed S MODE
  MODE: --olat DIRECTIONS.csv --out-dir DIR --irradiance E
          one EXR per line of DIRECTIONS.csv (x,y,z towards the light, our
          axes), lit by a sun of irradiance E alone: DIR/olat_NNN.exr
      | --lamps LAMPS.json --out X.exr
          lit by every lamp of LAMPS.json ({"lamps": [{"direction": [x, y, z],
          "irradiance": [r, g, b]}, ...]}) at once
      | --hdri MAP.exr --out X.exr
          lit by the lat-long map (our orientation, docs/design.md)

A sun lamp of angle 0 is a distant point light: strength E lights a surface
facing it with irradiance E, the meaning of a light's intensity in our lights
file (docs/formats.md), and of Phi_k, the map's integral over light k's cell.
"""

import json
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_scene as scene  # noqa: E402  (the scene building)
import render_cycles as rc  # noqa: E402  (the arguments every render takes)


def parse_args():
    p, argv = rc.scene_parser()
    p.add_argument("--samples", type=int, default=64)
    p.add_argument("--seed", type=int, default=1)
    mode = p.add_mutually_exclusive_group(required=True)
    mode.add_argument("--olat", help="a CSV of x,y,z directions, one light per line")
    mode.add_argument("--lamps", help="a JSON of lamps: direction and RGB irradiance")
    mode.add_argument("--hdri", help="a lat-long map lighting the scene")
    p.add_argument("--out-dir", help="--olat: where the images go")
    p.add_argument("--irradiance", type=float, default=1.0, help="--olat: each sun's")
    p.add_argument("--out", help="--lamps, --hdri: the render")
    return p.parse_args(argv)


def render(path):
    bpy.context.scene.render.filepath = os.path.abspath(path)
    bpy.ops.render.render(write_still=True)


def render_olat(a):
    directions = [[float(v) for v in line.split(",")]
                  for line in open(a.olat) if line.strip()]
    suns = [scene.add_sun(k, d, [a.irradiance] * 3) for k, d in enumerate(directions)]
    os.makedirs(a.out_dir, exist_ok=True)
    for k, sun in enumerate(suns):
        for other in suns:
            other.hide_render = other is not sun
        render(os.path.join(a.out_dir, f"olat_{k:03d}.exr"))
        print(f"olat {k + 1}/{len(suns)}", flush=True)


def main():
    a = parse_args()
    scene.build_scene(a.scene, a.width, a.height)
    scene.add_world(os.path.abspath(a.hdri) if a.hdri else None)
    scene.configure_cycles(a.samples, a.seed, 0)
    if a.olat:
        render_olat(a)
        return
    if a.lamps:
        lamps = json.load(open(a.lamps))["lamps"]
        lit = [lamp for lamp in lamps if max(lamp["irradiance"]) > 0]
        for k, lamp in enumerate(lit):
            scene.add_sun(k, lamp["direction"], lamp["irradiance"])
        print(f"{len(lit)} of {len(lamps)} lamps lit", flush=True)
    render(a.out)


main()
