"""Renders one of our scene files with Blender's Cycles, direct light or up
to K bounces (--bounces), under a lattice exported by `adaptive-cpca envmap`
and/or local lights (--light, as `relight` takes them), and compares the
result with our dense relight of the same scene.

Run by scripts/cycles/compare.sh inside Blender:
  blender -b --factory-startup --python render_cycles.py -- \
      --scene S.json --width W --height H --env lattice.exr --ours ours.exr \
      --out cycles.exr --samples N --seed S [--bounces K] [--camera EYE,TARGET,UP,FOV] \
      [--light SPEC ...] [--sources SOURCES.json] [--closed-form]
or, for scripts/cycles/labels.sh, with --passes instead of --ours: the Normal,
Depth and DiffCol passes into --out as a multilayer EXR.

The scene is built as the fair comparison of docs/design.md section 7 asks
(cycles_scene.py).
"""

import argparse
import json
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_scene import (add_light, add_map_sources, add_world, build_scene,  # noqa: E402
                          configure_cycles, parse_light)


def scene_parser():
    """The arguments after Blender's `--`, and a parser of the scene and image
    size every render takes."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--scene", required=True)
    p.add_argument("--width", type=int, required=True)
    p.add_argument("--height", type=int, required=True)
    return p, argv


def parse_args():
    p, argv = scene_parser()
    p.add_argument("--camera", help="eye,target,up as 9 numbers then fov (ours after framing)")
    p.add_argument("--env", required=True, help="lat-long EXR of the lattice, or none (black)")
    p.add_argument("--sources", help="`envmap --without-sources --json` of the map: its "
                   "sources as Sun lamps of their angle and irradiance (--env the rest)")
    p.add_argument("--light", action="append", default=[],
                   help="a local light as `relight --light` takes it (point or sphere)")
    p.add_argument("--closed-form", action="store_true",
                   help="also compare Cycles with the closed form of a sphere light over "
                        "the scene's one plane (diffuse, the light above its horizon)")
    p.add_argument("--ours", help="our dense relight, black background, EXR")
    p.add_argument("--also", action="append", default=[], metavar="NAME=EXR",
                   help="another image of ours (a model's relight) against the same render")
    p.add_argument("--out", required=True)
    p.add_argument("--samples", type=int, default=512)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--bounces", type=int, default=0, help="indirect bounces (ours: --bounces)")
    p.add_argument("--json", help="write the comparison here")
    p.add_argument("--passes", action="store_true",
                   help="write --out as a multilayer EXR with the Normal, Depth and DiffCol "
                        "passes (labels.sh compares them with our labels); no comparison")
    return p.parse_args(argv)


# ---------------------------------------------------------------- materials


# ---------------------------------------------------------------- geometry


# ---------------------------------------------------------------- camera, world, render


# ---------------------------------------------------------------- local lights


def camera_rays(eye, target, up, fov, width, height, per_side):
    """Our pinhole's rays (Y-up world) through per_side^2 stratified points of
    every pixel: origins and directions, shape (height, width, per_side^2, 3)."""
    eye, target, up = (np.array(x, dtype=np.float64) for x in (eye, target, up))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    t = math.tan(math.radians(fov) / 2)
    offsets = (np.arange(per_side) + 0.5) / per_side
    sx = (np.arange(width)[:, None] + offsets[None, :]).reshape(-1)
    sy = (np.arange(height)[:, None] + offsets[None, :]).reshape(-1)
    x = (2 * sx / width - 1) * t * width / height
    y = (1 - 2 * sy / height) * t
    d = (forward[None, None] + x[None, :, None] * right[None, None]
         + y[:, None, None] * true_up[None, None])
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    d = d.reshape(height, per_side, width, per_side, 3).transpose(0, 2, 1, 3, 4)
    return eye, d.reshape(height, width, per_side * per_side, 3)


def closed_form_plane(scene_json, light, camera, width, height):
    """Radiance of a diffuse plane of albedo a under a point light of intensity
    I, a I cos(theta) / (pi D^2) at a point D from it, theta from the normal;
    or under a sphere of radiance L and radius r wholly above its horizon,
    a L (r / D)^2 cos(theta) (its irradiance is a point source's of intensity
    pi r^2 L). Per pixel, the mean over 8x8 samples; with a mask of pixels
    whose every sample meets the plane."""
    planes = [o for o in scene_json["objects"] if o.get("shape") == "plane"]
    if len(planes) != 1 or len(scene_json["objects"]) != 1:
        raise SystemExit("--closed-form needs a scene of one plane")
    plane = planes[0]
    material = plane["material"]
    if material.get("type", "diffuse") != "diffuse" or "texture" in material:
        raise SystemExit("--closed-form needs an untextured diffuse plane")
    n = np.array(plane["normal"], dtype=np.float64)
    n /= np.linalg.norm(n)
    c = np.array(plane["center"], dtype=np.float64)
    eye, dirs = camera_rays(*camera, width, height, 8)
    denom = dirs @ n
    t = ((c - eye) @ n) / np.where(np.abs(denom) > 1e-12, denom, np.nan)
    hit = eye + t[..., None] * dirs
    # The quad of add_plane: its in-plane axes a, b and half size.
    helper = np.array([0, 1, 0.0]) if abs(n[1]) < 0.9 else np.array([1, 0, 0.0])
    a = np.cross(n, helper)
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    half = 0.5 * plane["size"]
    rel = hit - c
    inside = (t > 0) & (np.abs(rel @ a) <= half) & (np.abs(rel @ b) <= half)
    centre = np.array(light["position"], dtype=np.float64)
    to_light = centre - hit
    dist = np.linalg.norm(to_light, axis=-1)
    cos_theta = (to_light @ n) / dist
    r = light["radius"]
    if not np.all(cos_theta[inside] * dist[inside] > r):
        raise SystemExit("--closed-form: the sphere dips below the plane's horizon somewhere")
    albedo = np.array(material.get("albedo", [0.5, 0.5, 0.5]), dtype=np.float64)
    per_sample = np.where(inside, r * r * cos_theta / dist ** 2 if r > 0
                          else cos_theta / (math.pi * dist ** 2), 0.0)
    radiance = per_sample.mean(axis=2)[..., None] * albedo * np.array(light["emission"])
    return radiance, inside.all(axis=2)


def compare_closed_form(expected, full, cycles_path, width, height):
    cycles = pixels(cycles_path, width, height)[..., :3]
    d = cycles[full] - expected[full]
    return {
        "relative_l2": float(np.sqrt((d ** 2).sum() / (expected[full] ** 2).sum())),
        "energy_ratio": float(cycles[full].sum() / expected[full].sum()),
        "pixels": int(full.sum()),
    }


def pixels(path, width, height):
    image = bpy.data.images.load(path)
    image.colorspace_settings.name = "Linear"
    data = np.array(image.pixels[:], dtype=np.float64).reshape(height, width, image.channels)
    return data[::-1]  # Blender stores the bottom row first


def compare(ours_path, cycles_path, width, height):
    ours = pixels(ours_path, width, height)
    cycles = pixels(cycles_path, width, height)
    covered = cycles[..., 3] > 0
    full = cycles[..., 3] > 0.999
    edge = covered & ~full
    diff = ours[..., :3] - cycles[..., :3]

    def rel(mask):
        d = diff[mask]
        return float(np.sqrt((d ** 2).sum() / max((cycles[..., :3][mask] ** 2).sum(), 1e-300)))

    return {
        "relative_l2": rel(covered),
        "relative_l2_full_pixels": rel(full),
        "relative_l2_edge_pixels": rel(edge) if edge.any() else 0.0,
        "energy_ratio": float(ours[..., :3][covered].sum() / cycles[..., :3][covered].sum()),
        "covered_pixels": int(covered.sum()),
        "edge_pixels": int(edge.sum()),
    }


def main():
    a = parse_args()
    scene_json, (eye, target, up, fov) = build_scene(a.scene, a.width, a.height, a.camera)
    add_world(None if a.env == "none" else os.path.abspath(a.env))
    if a.sources:
        with open(a.sources) as f:
            add_map_sources(json.load(f)["sources"])
    lights = [parse_light(spec) for spec in a.light]
    for i, light in enumerate(lights):
        add_light(light, i)
    configure_cycles(a.samples, a.seed, a.bounces)
    for o in bpy.context.scene.objects:  # for the log: what Cycles renders
        print("object", o.name, o.type, [s.material.name for s in o.material_slots if s.material],
              tuple(round(v, 4) for v in o.dimensions))
    bpy.context.scene.render.filepath = os.path.abspath(a.out)
    if a.passes:  # the label passes beside Combined, one multilayer file
        layer = bpy.context.view_layer
        layer.use_pass_normal = layer.use_pass_z = layer.use_pass_diffuse_color = True
        bpy.context.scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
        bpy.ops.render.render(write_still=True)
        return
    bpy.ops.render.render(write_still=True)
    result = compare(os.path.abspath(a.ours), os.path.abspath(a.out), a.width, a.height)
    result.update({"scene": a.scene, "samples": a.samples, "seed": a.seed, "lights": a.light})
    for also in a.also:
        name, path = also.split("=", 1)
        result.setdefault("also", {})[name] = compare(os.path.abspath(path), os.path.abspath(a.out),
                                                      a.width, a.height)
    if a.closed_form:
        if len(lights) != 1 or a.env != "none":
            raise SystemExit("--closed-form needs one light and --env none")
        expected, full = closed_form_plane(scene_json, lights[0], (eye, target, up, fov),
                                           a.width, a.height)
        result["cycles_vs_closed_form"] = compare_closed_form(
            expected, full, os.path.abspath(a.out), a.width, a.height)
        result["ours_vs_closed_form"] = compare_closed_form(
            expected, full, os.path.abspath(a.ours), a.width, a.height)
    print("cycles-comparison " + json.dumps(result))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=2)


if __name__ == "__main__":  # render_olat.py imports the scene building
    main()
