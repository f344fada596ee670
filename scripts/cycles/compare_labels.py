"""Our labels (OUT/ours_labels_{albedo,normal,depth,mask,object}.npy) against
Cycles' passes (OUT/cycles.exr, multilayer): relative L2 over interior pixels
(each pixel and its eight neighbours covered wholly, by one object, at depths
within 2% and normals within 10 degrees: no silhouette, occlusion edge or
crease inside the pixel, where our first-hit normal and Cycles' mean of
its samples differ by design), for
scripts/cycles/labels.sh. Cycles' Depth is tried both as planar depth and as
distance from the camera centre: the one that agrees is its convention.

  python3 compare_labels.py OUT EYE,TARGET,UP,FOV
"""

import json
import sys

import numpy as np

import adaptive_cpca as ac


def passes(path):
    """Cycles' passes by name: Normal (H, W, 3), Depth (H, W), DiffCol (H, W, 3), alpha."""
    image = ac.read_image(path)
    names = ac.image_channel_names(path)

    def channels(layer, suffixes):
        found = [next(i for i, n in enumerate(names) if n.endswith(f"{layer}.{s}")) for s in suffixes]
        return image[..., found]

    return {"normal": channels("Normal", "XYZ"), "depth": channels("Depth", "Z")[..., 0],
            "albedo": channels("DiffCol", "RGB"), "alpha": channels("Combined", "A")[..., 0]}


def ray_cosines(camera, width, height):
    """cos of the angle between each pixel centre's ray and the view axis."""
    v = [float(x) for x in camera.split(",")]
    fov = np.radians(v[9])
    half = np.tan(fov / 2)
    x = (np.arange(width) + 0.5) / height * 2 * half - width / height * half
    y = (np.arange(height) + 0.5) / height * 2 * half - half
    xx, yy = np.meshgrid(x, y)
    return 1 / np.sqrt(1 + xx ** 2 + yy ** 2)


def main():
    out, camera = sys.argv[1], sys.argv[2]
    ours = {name: np.load(f"{out}/ours_labels_{name}.npy")
            for name in ("albedo", "normal", "depth", "mask", "object")}
    cycles = passes(f"{out}/cycles.exr")
    # Blender's world is Z-up: our (x, y, z) is its (x, -z, y).
    n = cycles["normal"]
    cycles["normal"] = np.stack([n[..., 0], n[..., 2], -n[..., 1]], axis=-1)
    full = (ours["mask"] == 1) & (cycles["alpha"] > 0.999)
    interior = full.copy()
    depth, object_id, normal = ours["depth"], ours["object"], ours["normal"]
    for dy in (-1, 0, 1):  # every neighbour covered, by the same object, at
        for dx in (-1, 0, 1):  # about the same depth and facing within 10
            shifted = lambda a: np.roll(np.roll(a, dy, 0), dx, 1)  # degrees: no edge
            interior &= shifted(full) & (shifted(object_id) == object_id)
            interior &= np.abs(shifted(depth) - depth) < 0.02 * depth
            interior &= (shifted(normal) * normal).sum(axis=-1) > np.cos(np.radians(10))
    interior[0, :] = interior[-1, :] = interior[:, 0] = interior[:, -1] = False

    def rel(a, b):
        d = (a - b)[interior]
        return float(np.sqrt((d ** 2).sum() / (b[interior] ** 2).sum()))

    h, w = ours["depth"].shape
    cosines = ray_cosines(camera, w, h)
    result = {
        "interior_pixels": int(interior.sum()),
        "normal": rel(ours["normal"], cycles["normal"]),
        "albedo": rel(ours["albedo"], cycles["albedo"]),
        "depth_if_cycles_is_planar": rel(ours["depth"], cycles["depth"]),
        "depth_if_cycles_is_distance": rel(ours["depth"], cycles["depth"] * cosines),
    }
    json.dump(result, open(f"{out}/comparison.json", "w"), indent=2)
    for key, value in result.items():
        print(f"{key:30s} {value if key == 'interior_pixels' else f'{100 * value:.3f}%'}")


main()
