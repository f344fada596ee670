"""Reads a batch the CLI wrote (`adaptive-cpca relight ... --out DIR`) into
numpy batches: images as (N, H, W, 3) float32 and each frame's labels from
DIR/manifest.jsonl (docs/formats.md, "Batch manifest"). numpy, json and the
module only: no deep-learning framework.

  PYTHONPATH=build/python /usr/bin/python3 python/examples/load_dataset.py DIR --batch 8
"""

import argparse
import json
import os

import numpy as np

import adaptive_cpca as ac


def read_manifest(directory):
    """Every frame's labels, in frame order: one dict per manifest.jsonl line."""
    with open(os.path.join(directory, "manifest.jsonl")) as f:
        return [json.loads(line) for line in f if line.strip()]


def frame_image(frame, directory):
    """The frame's first EXR as (H, W, 3) float32 linear RGB. Output paths are
    as the batch wrote them; where one does not resolve from here, the file of
    that name in the directory is read, so a dataset can be read from anywhere."""
    path = next(p for p in frame["outputs"] if p.endswith(".exr"))
    if not os.path.exists(path):
        path = os.path.join(directory, os.path.basename(path))
    return ac.read_image(path)[..., :3]


def batches(directory, batch_size, shuffle=False, seed=0):
    """Yields (images, labels): images (B, H, W, 3) float32; labels a dict of
    arrays, `sh9` (B, 9, 3), `yaw`, `pitch`, `roll`, `exposure` (B,), and
    lists `env`, `env_sha256`, `lights`, `frame`."""
    frames = read_manifest(directory)
    order = np.arange(len(frames))
    if shuffle:
        np.random.default_rng(seed).shuffle(order)
    for start in range(0, len(order), batch_size):
        chosen = [frames[i] for i in order[start:start + batch_size]]
        images = np.stack([frame_image(f, directory) for f in chosen]).astype(np.float32)
        labels = {
            "sh9": np.array([f["sh9"] for f in chosen], dtype=np.float64),
            **{k: np.array([f[k] for f in chosen], dtype=np.float64)
               for k in ("yaw", "pitch", "roll", "exposure")},
            **{k: [f.get(k) for f in chosen] for k in ("env", "env_sha256", "lights", "frame")},
        }
        yield images, labels


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("directory", help="a batch's output directory (with manifest.jsonl)")
    p.add_argument("--batch", type=int, default=8)
    p.add_argument("--shuffle", action="store_true")
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    total = 0
    for images, labels in batches(a.directory, a.batch, a.shuffle, a.seed):
        total += len(images)
        print(f"batch of {len(images)}: images {images.shape}, sh9 {labels['sh9'].shape}, "
              f"mean radiance {images.mean():.4g}")
    print(f"{total} frames from {a.directory}")


if __name__ == "__main__":
    main()
