"""The fields a CLI frame's header holds (docs/formats.md, "Frame metadata")
for a view TorchRelighter makes, so training code can label its own frames
as `relight` and `batch` label theirs."""

import hashlib
import os

import h5py
import numpy as np
import torch

from .._contract import VERSION
from .camera import world_to_camera_and_ndc


def file_digest(path):
    """A file's sha256 digest, hex, as the CLI's source_sha256 and env_sha256 give it."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def frame_fields(relighter, env, yaw=0.0, pitch=0.0, roll=0.0, exposure=0.0):
    """A dict of env, yaw, pitch, roll, exposure, lights, sh9 (of the
    lattice lighting, as the manifest's), colorInteropID, worldToCamera and
    worldToNDC (16 floats, row by row, OpenEXR's conventions), source,
    source_sha256, method, cost_per_pixel (a model's) and version. env: a spec or map file (a file's
    digest as env_sha256)."""
    env_spec = env if isinstance(env, str) else getattr(env, "spec", None)
    fields = {"env": env_spec or "", "yaw": float(yaw), "pitch": float(pitch),
              "roll": float(roll), "exposure": float(exposure), "lights": [],
              "colorInteropID": "lin_rec709_scene"}
    if env_spec and os.path.isfile(env_spec):
        fields["env_sha256"] = file_digest(env_spec)
    lighting = relighter.lighting(env, yaw, pitch, roll, dtype=torch.float64)
    fields["sh9"] = relighter.sh9(lighting).cpu().numpy().tolist()
    if relighter.camera is not None:
        to_camera, to_ndc = world_to_camera_and_ndc(relighter.camera, relighter.width,
                                                    relighter.height)
        fields["worldToCamera"] = to_camera.astype(np.float32).ravel().tolist()
        fields["worldToNDC"] = to_ndc.astype(np.float32).ravel().tolist()
    with h5py.File(relighter.path, "r") as f:
        method = f.attrs.get("method", "")
        cost = f.attrs.get("cost_per_pixel")
    if cost is not None:  # a model, relit at its full ranks
        fields["cost_per_pixel"] = float(cost)
    fields.update(source=os.path.basename(relighter.path),
                  source_sha256=file_digest(relighter.path),
                  method=method.decode() if isinstance(method, bytes) else str(method),
                  version=VERSION)
    return fields
