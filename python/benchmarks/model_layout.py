"""A model file's layout, and a model file of that layout with seeded values.

A GPU machine may be too far away to copy a 200 MB model to: its layout (the
image size, N, each cluster's rank and rows, the texels some pixel sees, the
stored precisions) is a few kB, and a model of the same layout relights at
the same speed.

  python3 model_layout.py export MODEL LAYOUT.json
  python3 model_layout.py write LAYOUT.json OUT.h5 [--seed 1]

The file written holds what docs/formats.md's model file holds for
`adaptive_cpca.torch` to relight it (not the labels): seeded values, every
row's pixel inside the image, a camera looking down -Z. numpy and h5py only.
"""

import argparse
import json
import os

import h5py
import numpy as np

ATTRIBUTES = ("width", "height", "cubemap", "channels", "coeffs", "bases", "has_mean", "method")


def _plain(value):
    if isinstance(value, bytes):
        return value.decode()
    return value.item() if hasattr(value, "item") else value


def export_layout(model):
    with h5py.File(model, "r") as f:
        basis = f["global_basis"][:]
        layout = {name: _plain(f.attrs[name]) for name in ATTRIBUTES if name in f.attrs}
        layout.update({
            "source": os.path.basename(model), "global_bases": int(basis.shape[1]),
            "seen_texels": np.flatnonzero(np.abs(basis).sum(1) > 0).tolist(),
            "ranks": f["cluster_rank"][:].tolist(),
            "rows": np.diff(f["cluster_row_offsets"][:]).tolist()})
    return layout


def write_model(layout, out, seed=1):
    rng = np.random.default_rng(seed)
    width, height = layout["width"], layout["height"]
    channels, n = layout.get("channels", 1), layout["global_bases"]
    l = 6 * layout["cubemap"] ** 2
    ranks, rows = np.array(layout["ranks"]), np.array(layout["rows"])
    p = int(rows.sum())
    seen = np.array(layout["seen_texels"])
    basis = np.zeros((channels * l, n), np.float32)
    q, _ = np.linalg.qr(rng.standard_normal((len(seen), n)))
    basis[seen] = q
    storage = {"f32": np.float32, "f16": np.float16, "i8": np.int8}
    total_rank = int(ranks.sum())
    entries = int((ranks * rows).sum())
    if layout.get("coeffs", "f32") == "i8":
        coefficients = rng.integers(-127, 128, entries, dtype=np.int8)
        scale = rng.uniform(1e-3, 1e-2, total_rank).astype(np.float32)
    else:
        coefficients = rng.standard_normal(entries).astype(storage[layout.get("coeffs", "f32")])
        scale = np.ones(total_rank, np.float32)
    bases = rng.standard_normal(total_rank * n) / np.sqrt(n)
    with h5py.File(out, "w", libver=("v110", "v110")) as f:
        f.attrs["format"] = "adaptive-cpca model"
        f.attrs["version"] = 6
        for name in ATTRIBUTES:
            if name in layout:
                f.attrs[name] = layout[name]
        f.attrs["occupied_pixels"] = p
        f.attrs["camera_eye"] = np.array([0.0, 0.0, 3.0])
        f.attrs["camera_target"] = np.zeros(3)
        f.attrs["camera_up"] = np.array([0.0, 1.0, 0.0])
        f.attrs["camera_fov_deg"] = 40.0
        f["global_basis"] = basis
        f["pixels"] = np.sort(rng.choice(width * height, p, replace=False)).astype(np.int32)
        f["albedo"] = rng.uniform(0.2, 0.8, (p, 3)).astype(np.float32)
        f["coverage"] = np.ones(p, np.float32)
        f["cluster_rows"] = rng.permutation(p).astype(np.int32)
        f["cluster_row_offsets"] = np.concatenate([[0], np.cumsum(rows)]).astype(np.int64)
        f["cluster_rank"] = ranks.astype(np.int32)
        f["cluster_basis_offsets"] = np.concatenate([[0], np.cumsum(ranks) * n]).astype(np.int64)
        f["bases"] = bases.astype(storage[layout.get("bases", "f32")])
        f["means"] = (rng.standard_normal(len(ranks) * n) / np.sqrt(n)).astype(
            storage[layout.get("bases", "f32")])
        f["coefficient_offsets"] = np.concatenate([[0], np.cumsum(ranks * rows)]).astype(np.int64)
        f["coefficients"] = coefficients
        f["coefficient_scale"] = scale
        f.attrs["complete"] = 1


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    e = sub.add_parser("export")
    e.add_argument("model")
    e.add_argument("layout")
    w = sub.add_parser("write")
    w.add_argument("layout")
    w.add_argument("out")
    w.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    if a.command == "export":
        with open(a.layout, "w") as f:
            json.dump(export_layout(a.model), f)
    else:
        with open(a.layout) as f:
            write_model(json.load(f), a.out, a.seed)


if __name__ == "__main__":
    main()
