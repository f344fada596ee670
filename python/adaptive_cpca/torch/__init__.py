"""Relighting in PyTorch: a model file held on any torch device.

Pure Python over PyTorch and h5py (no compiled part), reading model files
exactly as docs/formats.md ("Model file") documents them, so it runs where
the compiled module was not built for the Python at hand (a GPU machine's).
Works on torch 1.13 (Debian 12's) and 2.x.

    from adaptive_cpca.torch import TorchRelighter, RelightDataset
    r = TorchRelighter("plant-model.h5", device="cuda")
    sky = r.environment("sky")                  # or a map file, or a [H, 2H, 3] tensor
    lighting = r.lighting(sky, yaw=30)          # [l, 3], made on the device
    images = r.relight(torch.stack([lighting, r.lighting(sky, yaw=60)]))  # [2, 3, H, W]

A lattice lighting holds, per column (a cube-lattice texel, or a captured
set's light), the radiance integrated over its solid angle, as the CLI and
`Relighter.lighting(env).values` make it; `lighting()` integrates it here
with the lattice's exact texel solid angles (adaptive_cpca.torch.lighting).
"""

from .dataset import RelightDataset
from .lighting import Environment, rotation_matrix
from .relighter import TorchRelighter

__all__ = ["TorchRelighter", "RelightDataset", "Environment", "rotation_matrix"]
