"""Reads a batch the CLI wrote (`adaptive-cpca relight ... --out DIR`, its
frames as files or packed in tars with --shard-size) into numpy batches: images as (N, H, W, 3) float32, each frame's labels from
DIR/manifest.jsonl (docs/formats.md, "Batch manifest") and, for a batch made
with --aov, its shading and the view's per-pixel labels (docs/datasets.md).
numpy, json and the module only: no deep-learning framework.

  PYTHONPATH=build/python /usr/bin/python3 python/examples/load_dataset.py DIR --batch 8
"""

import argparse
import io
import json
import os
import tarfile
import tempfile

import numpy as np

import adaptive_cpca as ac


def read_manifest(directory):
    """Every frame's labels, in frame order: one dict per manifest.jsonl line."""
    with open(os.path.join(directory, "manifest.jsonl")) as f:
        return [json.loads(line) for line in f if line.strip()]


def resolved(path, directory):
    """A manifest's path: relative to the dataset's directory (docs/formats.md,
    "Batch manifest"), so a dataset moved or copied elsewhere still loads.
    Manifests of earlier versions held paths as typed: where such a path no
    longer resolves, the file of that name in the directory."""
    joined = os.path.join(directory, path)
    return joined if os.path.exists(joined) else os.path.join(directory, os.path.basename(path))


_open_shards = {}


def shard_member(directory, shard, name):
    """A member's bytes from one of a sharded batch's tars (--shard-size)."""
    path = os.path.join(directory, shard)
    if path not in _open_shards:
        _open_shards[path] = tarfile.open(path)
    return _open_shards[path].extractfile(name).read()


def decoded(name, data):
    """An .npy or EXR file's bytes as an array (EXR through a file: the reader takes paths)."""
    if name.endswith(".npy"):
        return np.load(io.BytesIO(data))
    with tempfile.NamedTemporaryFile(suffix=os.path.splitext(name)[1]) as f:
        f.write(data)
        f.flush()
        return ac.read_image(f.name)


def frame_image(frame, directory, key="outputs"):
    """The frame's first EXR (or, for shading, .npy) as (H, W, 3) float32 linear
    RGB: from its file, or in a sharded batch from its shard's member."""
    name = next(p for p in frame[key] if p.endswith((".exr", ".npy")))
    if "shard" in frame:
        return decoded(name, shard_member(directory, frame["shard"], name))[..., :3]
    path = resolved(name, directory)
    return (np.load(path) if path.endswith(".npy") else ac.read_image(path))[..., :3]


def shard_samples(directory):
    """A sharded batch's samples as WebDataset reads them, shard after shard:
    (key, {suffix: bytes}), each frame's files under its index (00123.exr,
    00123.shading.exr, 00123.json: its manifest line) and each view's labels
    once per shard under their own names (labels.exr, ...)."""
    name = os.path.basename(os.path.normpath(os.path.abspath(directory)))
    with open(os.path.join(directory, f"{name}-shards.json")) as f:
        index = json.load(f)
    for shard in index["shards"]:
        with tarfile.open(os.path.join(directory, shard["name"])) as tar:
            key, files = None, {}
            for member in tar:
                k, suffix = member.name.split(".", 1)
                if k != key and files:
                    yield key, files
                    files = {}
                key = k
                files[suffix] = tar.extractfile(member).read()
            if files:
                yield key, files


def view_labels(frame, directory):
    """The per-pixel labels of the frame's view by AOV name (albedo, normal,
    tangent, depth, position, mask, object): from the .npy files where the batch wrote
    them, else from labels.exr's channels. Empty for a batch without --aov."""
    paths = [resolved(p, directory) for p in frame.get("labels", [])]
    npys = [p for p in paths if p.endswith(".npy")]
    if npys:  # labels_AOV.npy
        return {os.path.basename(p)[:-4].split("_")[-1]: np.load(p) for p in npys}
    if not paths:
        return {}
    # labels.exr: channels grouped by layer, each AOV's in the order written.
    image = ac.read_image(paths[0])
    channels = {"albedo": ["albedo.R", "albedo.G", "albedo.B"], "normal": ["N.X", "N.Y", "N.Z"],
                "tangent": ["T.X", "T.Y", "T.Z"], "depth": ["Z"], "position": ["P.X", "P.Y", "P.Z"], "mask": ["A"],
                "object": ["object"]}
    names = ac.image_channel_names(paths[0])
    labels = {}
    for aov, wanted in channels.items():
        if all(c in names for c in wanted):
            value = image[..., [names.index(c) for c in wanted]]
            labels[aov] = value[..., 0].astype(np.int32) if aov == "object" else (
                value[..., 0] if len(wanted) == 1 else value)
    return labels


def batches(directory, batch_size, shuffle=False, seed=0):
    """Yields (images, labels): images (B, H, W, 3) float32; labels a dict of
    arrays, `sh9` (B, 9, 3), `yaw`, `pitch`, `roll`, `exposure` (B,), with
    --aov shading `shading` (B, H, W, 3), and lists `env`, `env_sha256`,
    `lights`, `frame`, `sample` (None unless drawn). The view's per-pixel
    labels: view_labels()."""
    frames = read_manifest(directory)
    order = np.arange(len(frames))
    if shuffle:
        np.random.default_rng(seed).shuffle(order)
    for start in range(0, len(order), batch_size):
        chosen = [frames[i] for i in order[start:start + batch_size]]
        images = np.stack([frame_image(f, directory) for f in chosen]).astype(np.float32)
        labels = {
            **({"shading": np.stack([frame_image(f, directory, "shading") for f in chosen])}
               if all(f.get("shading") for f in chosen) else {}),
            "sh9": np.array([f["sh9"] for f in chosen], dtype=np.float64),
            **{k: np.array([f[k] for f in chosen], dtype=np.float64)
               for k in ("yaw", "pitch", "roll", "exposure")},
            **{k: [f.get(k) for f in chosen]
               for k in ("env", "env_sha256", "lights", "frame", "sample")},
        }
        yield images, labels


def frame_lighting(path):
    """A frame's lighting, camera and source from its own file (docs/formats.md,
    "Frame metadata"): what its manifest line says, for a frame copied out of
    its dataset. EXR and PNG frames; .npy frames hold none."""
    from adaptive_cpca.io import read_frame_metadata
    return read_frame_metadata(path)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("directory", help="a batch's output directory (with manifest.jsonl)")
    p.add_argument("--frame", help="print this frame file's own lighting and exit")
    p.add_argument("--batch", type=int, default=8)
    p.add_argument("--shuffle", action="store_true")
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    if a.frame:
        fields = frame_lighting(a.frame)
        print(json.dumps({k: fields.get(k) for k in ("env", "yaw", "pitch", "roll", "exposure",
                                                    "lights", "source", "method")}))
        return
    total = 0
    for images, labels in batches(a.directory, a.batch, a.shuffle, a.seed):
        total += len(images)
        print(f"batch of {len(images)}: images {images.shape}, sh9 {labels['sh9'].shape}, "
              f"mean radiance {images.mean():.4g}")
    print(f"{total} frames from {a.directory}")


if __name__ == "__main__":
    main()
