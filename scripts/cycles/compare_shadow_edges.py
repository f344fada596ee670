"""Relative L2 against Cycles within 2 px of the brightest source's shadow
edges, for our exact frame (ours.exr) and the whole map on the lattice
(lattice-sun.exr); run by compare.sh --sun auto|K when the map has sources.

A shadow edge lies between two 4-neighbours of one object, both wholly
covered (a silhouette is not a shadow), whose normals
differ by less than 2.6 degrees (a crease is not a shadow), where the source
alone (sun-alone.exr, our frame under a `sun:` disc of its direction, size and
luminance) falls by half or more from one to the other, the brighter of the
two above 10% of the source's brightest pixel. The mask is every covered
pixel within 2 px (Chebyshev) of one, and the figures go into
comparison.json as "shadow_edges".

  PYTHONPATH=build/python python3 compare_shadow_edges.py OUT_DIR
"""

import json
import sys

import numpy as np

import adaptive_cpca as ac


def shadow_edge_mask(sun_alone, objects, normals, full, covered, reach=2):
    lum = sun_alone[..., :3] @ np.array([0.2126, 0.7152, 0.0722])
    floor = 0.1 * lum[covered].max()
    edge = np.zeros_like(covered)
    for axis in (0, 1):
        a = lum
        b = np.roll(lum, -1, axis=axis)
        same = (objects == np.roll(objects, -1, axis=axis)) & full & np.roll(full, -1, axis)
        same &= (normals * np.roll(normals, -1, axis=axis)).sum(-1) > 0.999
        last = [slice(None)] * 2
        last[axis] = -1
        same[tuple(last)] = False  # no wrap-around
        high = np.maximum(a, b)
        step = same & (high > floor) & (np.minimum(a, b) <= 0.5 * high)
        edge |= step | np.roll(step, 1, axis=axis)
    padded = np.pad(edge, reach)
    h, w = edge.shape
    near = np.zeros_like(edge)
    for dy in range(2 * reach + 1):
        for dx in range(2 * reach + 1):
            near |= padded[dy:dy + h, dx:dx + w]
    return near & covered


def main():
    out = sys.argv[1]
    cycles = ac.read_image(f"{out}/cycles.exr")
    covered = cycles[..., 3] > 0
    labels = ac.Relighter(f"{out}/t.h5").labels("object,normal")
    mask = shadow_edge_mask(ac.read_image(f"{out}/sun-alone.exr"), labels["object"],
                            labels["normal"], cycles[..., 3] > 0.999, covered)
    reference = cycles[..., :3][mask]
    norm = (reference ** 2).sum()
    report = json.load(open(f"{out}/comparison.json"))
    figures = {"pixels": int(mask.sum())}
    images = {"ours": "ours.exr", "lattice": "lattice-sun.exr", "cycles_seed_2": "cycles-2.exr"}
    for name, path in images.items():
        image = ac.read_image(f"{out}/{path}")[..., :3][mask]
        figures[name] = float(np.sqrt(((image - reference) ** 2).sum() / norm))
    report["shadow_edges"] = figures
    json.dump(report, open(f"{out}/comparison.json", "w"), indent=2)
    print(f"within 2 px of the brightest source's shadow edges ({figures['pixels']} pixels): "
          f"ours {100 * figures['ours']:.2f}%, the lattice {100 * figures['lattice']:.2f}%, "
          f"Cycles vs Cycles {100 * figures['cycles_seed_2']:.2f}%")


if __name__ == "__main__":
    main()
