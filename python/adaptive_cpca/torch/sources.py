"""A map's sun and bright lamps lit exactly, for the torch relighter.

`sun=` means what it means for the CLI's `relight --sun` and
`adaptive_cpca.Relighter` (docs/lighting.md, "Lit exactly"): 'auto' splits
off the map's sources, 'off' keeps the whole map on the lattice, K at most
K sources. Torch cannot trace rays, so where the compiled part loads the
split, the lattice lighting of the rest and the sources' light (a shadow
ray per sample, per pixel) are made by it on the CPU, and moved to the
device, where the frame is composed. Where it does not load, or for a map
given as an array, the whole map goes through the lattice, with a warning
that says so. In a forked DataLoader worker the compiled part cannot run
(its thread pools do not survive a fork): there sun='auto' is refused, and
sun='off' works.
"""

import warnings

import numpy as np
import torch

from .._compiled import compiled_part, in_dataloader_worker

__all__ = ["SourceLighting", "check_sun"]


def check_sun(sun):
    """'auto', 'off' or a count of sources K >= 1, as the CLI takes --sun."""
    if sun in ("auto", "off") or (isinstance(sun, int) and not isinstance(sun, bool) and sun >= 1):
        return sun
    raise ValueError(f"sun {sun!r}: 'auto', 'off' or a number of sources (1 or more)")


class SourceLighting:
    """The compiled relighter of a model file, made on first use, splitting
    maps' sources for a TorchRelighter on `device`."""

    def __init__(self, path, device):
        self.path = path
        self.device = device
        self._relighter = None
        self._warned = set()

    def split(self, env, turns, stops, sun, dtype):
        """For each (yaw, pitch, roll) and exposure: the lattice lighting of
        what the lattice keeps [B, l, 3] (dtype) and the sources' light per
        row, file order [B, P, 3] float32 (None where no frame has any), both
        times 2^exposure, on the device; None where the split cannot be made
        (the caller integrates the whole map)."""
        relighter = self._relighter_for(env, sun)
        if relighter is None:
            return None
        compiled = env.compiled()
        values, lights = [], []
        for (yaw, pitch, roll), stop in zip(turns, stops):
            lighting = relighter.lighting(compiled, yaw=yaw, pitch=pitch, roll=roll, sun=sun)
            scale = 2.0 ** float(stop)
            values.append(torch.from_numpy(np.asarray(lighting.values)) * scale)
            light = relighter.source_light(lighting)
            lights.append(None if light is None else torch.from_numpy(light) * np.float32(scale))
        rows = None
        if any(light is not None for light in lights):
            size = next(light for light in lights if light is not None).shape
            rows = torch.stack([torch.zeros(size) if light is None else light
                                for light in lights]).to(self.device)
        return torch.stack(values).to(device=self.device, dtype=dtype), rows

    def _relighter_for(self, env, sun):
        if sun == "off":
            return None
        if in_dataloader_worker():
            raise RuntimeError(
                "sun='auto' lights a map's sun exactly through adaptive_cpca's compiled part, "
                "which does not run in a forked DataLoader worker: iterate with num_workers=0, "
                "or pass sun='off' to light the whole map through the lattice")
        core = compiled_part()
        if core is None:
            self._warn("compiled", "adaptive_cpca's compiled part did not load")
            return None
        if env.compiled() is None:
            self._warn("array", f"the map {env.name!r} was given as pixels, not a spec or file")
            return None
        if self._relighter is None:
            self._relighter = core.Relighter(self.path)
        return self._relighter

    def _warn(self, key, why):
        if key not in self._warned:
            self._warned.add(key)
            warnings.warn(f"{self.path}: {why}, so a map's sun and bright lamps go through the "
                          "lattice (their shadows come out soft and shifted by up to a texel); "
                          "sun='off' asks for that without this warning", stacklevel=4)
