#!/usr/bin/env python3
"""Ours with Cycles' masking, against Cycles (docs/results.md, "Anisotropic
materials against Cycles").

Our GGX uses Smith's height-correlated masking-shadowing G2 = 1 / (1 +
Lambda_i + Lambda_o); Blender 3.4's Cycles multiplies the two directions'
G1 = 1 / (1 + Lambda) (kernel/closure/bsdf_microfacet.h), which is never
brighter. This rescales each transport row of compare.sh's OUT_DIR/t.h5, texel
by texel, by the ratio of the two lobes (the shape with G1 G1 over ours,
evaluated at the first traced camera sample's normal and tangent), relights it
under the same lattice (lighting the whole map on the lattice, so only for a
map with no split sources, --sun off or none found), and prints the relative
L2 and the energy ratio against OUT_DIR/cycles.exr beside ours as rendered.

    python3 scripts/cycles/compare_masking.py OUT_DIR ENV
"""
import sys

import h5py
import numpy as np

import adaptive_cpca as ac


def lambdas(w_t, w_b, w_n, au, av):
    """Smith's Lambda for anisotropic GGX along w (transport/anisotropic_lobes.h)."""
    return (np.sqrt(1 + ((au * w_t) ** 2 + (av * w_b) ** 2) / (w_n * w_n)) - 1) / 2


def shapes(ks, au, av, n, t, v, d):
    """The GGX shape f/albedo with both maskings, over directions d [l, 3]."""
    b = np.cross(n, t)
    h = d + v
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    ci, co = d @ n, float(v @ n)
    x, y, hn = (h @ t) / au, (h @ b) / av, h @ n
    dist = 1 / (np.pi * au * av * (x * x + y * y + hn * hn) ** 2)
    li = lambdas(d @ t, d @ b, ci, au, av)
    lo = lambdas(float(v @ t), float(v @ b), co, au, av)
    above = (ci > 0) & (hn > 0)
    spec = np.where(above, dist / (4 * np.maximum(ci, 1e-12) * co), 0)
    diffuse = (1 - ks) / np.pi
    return diffuse + ks * spec / (1 + li + lo), diffuse + ks * spec / ((1 + li) * (1 + lo))


def main(out, env):
    with h5py.File(f"{out}/t.h5", "r") as f:
        rows = f["transport"][:].astype(np.float64)
        pixels, albedo, normal = f["pixels"][:], f["albedo"][:], f["normal"][:]
        coverage = f["coverage"][:][:, None]
        objects, width = f["object"][:], int(f.attrs["width"])
        height = int(f.attrs["height"])
        first = f["lamp_sample_start"][:-1]
        tangent, origin = f["lamp_sample_tangent"][:][first], f["lamp_sample_origin"][:][first]
        materials, directions = f["lamp_materials"][:], f["lattice_direction"][:]
        eye = f.attrs["camera_eye"]
    lighting = ac.Relighter(f"{out}/t.h5").lighting(ac.Environment(env)).values  # L x solid angle
    corrected = rows.copy()
    for r in range(rows.shape[0]):
        m = materials[objects[r]]
        if m[0] != 2 or m[1] == 0:  # only GGX lobes differ
            continue
        au, av = m[3], m[4] if m[4] > 0 else m[3]
        v = eye - origin[r]
        v /= np.linalg.norm(v)
        ours, cycles = shapes(m[1], au, av, normal[r].astype(np.float64),
                              tangent[r].astype(np.float64), v, directions)
        corrected[r] *= np.where(ours > 0, cycles / np.where(ours > 0, ours, 1), 0)
    reference = ac.read_image(f"{out}/cycles.exr")[..., :3].reshape(-1, 3)[pixels]
    rendered = ac.read_image(f"{out}/ours.exr")[..., :3].reshape(-1, 3)[pixels]
    print(f"{out}: {rows.shape[0]} rows, {width}x{height}")
    for name, image in (("ours (height-correlated G2)", rendered),
                        ("the same from its rows", coverage * albedo * (rows @ lighting)),
                        ("ours with Cycles' G1 G1", coverage * albedo * (corrected @ lighting))):
        error = np.linalg.norm(image - reference) / np.linalg.norm(reference)
        print(f"{name:28s} relative L2 {100 * error:.2f}%, energy ratio "
              f"{image.sum() / reference.sum():.4f}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
