"""Lighting made in PyTorch: environments integrated onto the cube lattice.

Pure Python over PyTorch, on any device, doing what the compiled `lighting/`
library does (docs/lighting.md, "Conventions" and "From a map to the
lattice"): every map integrated by area with the lattice's exact texel solid
angles, in float64, so that a torch lighting equals the CLI's to rounding.

- `constant:` radiance times each texel's exact solid angle;
- `sun:` the disc split into rings of equal solid angle (at least 16 rings per
  texel it spans), each sample carrying its share of the energy;
- lat-long maps: each pixel constant over its exact solid angle, split into
  sub-cells at most 1/8 of a texel across, each added to the texel that holds
  its rotated centre; horizontal cube crosses (4:3) likewise per face;
- `sky`: its smooth part on 4 x 4 exact-area sub-cells per texel, and its sun.

Rotation R = Rz(roll) Rx(pitch) Ry(yaw), degrees; the feature a map holds at
d0 lights from R d0. Maps are checked as the CLI checks them: finite,
negative ringing clamped (refused past 1% of the summed magnitude), 2:1
within 1% or 4:3.
"""

import math
import os
import warnings

import numpy as np
import torch

from .. import _contract as contract
from .._contract import (ENVIRONMENT_GRAMMARS, LATLONG_ASPECT_TOLERANCE, MAX_MAP_PIXELS,
                         MAX_NEGATIVE_SHARE, SILENT_NEGATIVE_SHARE)
from .._compiled import compiled_part
from ..io import read_image
from .lattice import CubeLattice, direction_from_angles, rotation_matrix
from .map_cells import add_cells, cross_cells, cross_radiance, latlong_cells, latlong_radiance

__all__ = ["CubeLattice", "Environment", "rotation_matrix", "ENVIRONMENT_GRAMMARS"]

_F64 = torch.float64
# Each built-in map's grammar by its prefix (lighting/environment.h).
_GRAMMAR = dict(contract.ENVIRONMENT_SPECS)


def _parse_numbers(text, spec):
    values = []
    for part in text.split(","):
        try:
            v = float(part)
        except ValueError:
            raise ValueError(f"environment {spec!r}: {part!r} is not a number") from None
        if not math.isfinite(v):
            raise ValueError(f"environment {spec!r}: {part!r} is not a finite number")
        values.append(v)
    return values


class Environment:
    """A lighting: a built-in map (`constant:`, `sun:`, `sky`), an image file
    (lat-long .exr/.hdr/.pfm, or a 4:3 horizontal cube cross) or a map given
    as an array or tensor [H, W, C] (row 0 at the zenith), held on a device.

    `integrate(lattice, rotations)` gives the lattice lighting of the map
    under each rotation [B, 3, 3]: [B, l, 3] (float64); `radiance(d)` the
    unrotated map's radiance toward d. What no rotation changes (the map's
    sub-cells and their solid angles) is made once per lattice resolution.
    pixels: a map file's pixels read already (its spec then names it)."""

    def __init__(self, spec, device="cpu", name=None, pixels=None):
        self.device = torch.device(device)
        self._sun = None
        self._constant = None
        self._map = None
        self._sky = False
        self._cached = {}
        self.spec = spec if isinstance(spec, str) else None
        if isinstance(spec, str):
            self._parse(spec, pixels)
        else:
            values = spec.detach().cpu().numpy() if torch.is_tensor(spec) else np.asarray(spec)
            self._set_pixels(name or "array", "the map given", values)

    # -- parsing ------------------------------------------------------------
    def _parse(self, spec, pixels=None):
        self.name = spec
        if spec == "sky":
            self._sky = True
            theta, phi, size = contract.SKY_SUN
            self._sun = _Sun(theta, phi, size, contract.SKY_SUN_RADIANCE, self.device)
            self._sky_sun = torch.tensor(direction_from_angles(math.radians(theta),
                                                               math.radians(phi)),
                                         dtype=_F64, device=self.device)
        elif spec.startswith("constant:"):
            v = _parse_numbers(spec[len("constant:"):], spec)
            if len(v) not in (1, 3):
                raise ValueError(f"environment {spec!r}: expected {_GRAMMAR['constant:']}")
            rgb = v * 3 if len(v) == 1 else v
            if min(rgb) < 0:
                raise ValueError(f"environment {spec!r}: radiance must be >= 0")
            self._constant = torch.tensor(rgb, dtype=_F64, device=self.device)
        elif spec.startswith("sun:"):
            v = _parse_numbers(spec[len("sun:"):], spec)
            if len(v) != 4:
                raise ValueError(f"environment {spec!r}: expected {_GRAMMAR['sun:']}")
            if not 0 < v[2] <= 180:
                raise ValueError(f"environment {spec!r}: SIZE_DEG must be in (0, 180]")
            if v[3] < 0:
                raise ValueError(f"environment {spec!r}: INTENSITY must be >= 0")
            self._sun = _Sun(v[0], v[1], v[2], (v[3],) * 3, self.device)
        elif pixels is not None or os.path.exists(spec):  # pixels: the file read already
            self._set_pixels(os.path.splitext(os.path.basename(spec))[0], spec,
                             read_image(spec) if pixels is None else pixels)
        else:
            raise ValueError(f"environment {spec!r}: no such file, and not "
                             f"{ENVIRONMENT_GRAMMARS}")

    def _set_pixels(self, name, where, values):
        """A map checked as makeEnvironmentFromPixels checks it."""
        self.name = name
        values = np.asarray(values, dtype=np.float32)
        if values.ndim == 2:
            values = values[:, :, None]
        if values.ndim != 3 or values.shape[2] < 1:
            raise ValueError(f"{where}: a map is H x W x C, not of shape {values.shape}")
        height, width = values.shape[:2]
        if width < 2 or height < 1 or width * height > MAX_MAP_PIXELS:
            raise ValueError(f"{where}: environment map size {width}x{height} is out of range")
        rgb = values[:, :, :3] if values.shape[2] >= 3 else np.repeat(values[:, :, :1], 3, 2)
        bad = np.argwhere(~np.isfinite(rgb))
        if len(bad):
            y, x, c = bad[0]
            raise ValueError(f"{where}: pixel ({x}, {y}) channel {c} is {rgb[y, x, c]}; "
                             "radiance must be finite")
        negative = rgb < 0
        if negative.any():
            count = int(negative.sum())
            share = float(-rgb[negative].astype(np.float64).sum() /
                          np.abs(rgb).astype(np.float64).sum())
            lowest = float(rgb.min())
            if share > MAX_NEGATIVE_SHARE:
                raise ValueError(
                    f"{where}: {count} negative values (down to {lowest:g}) hold "
                    f"{100 * share:g}% of the map's summed magnitude; more than "
                    f"{100 * MAX_NEGATIVE_SHARE:g}% is not ringing but a broken map")
            if share > SILENT_NEGATIVE_SHARE:
                warnings.warn(f"{where}: {count} negative values clamped to 0 (the most negative "
                              f"{lowest:g}, {100 * share:g}% of the summed magnitude)")
            rgb = np.maximum(rgb, 0)
        self._cross = width * 3 == height * 4 and width % 4 == 0
        if not self._cross:
            off = abs(width - 2 * height) / (2 * height)
            if off > LATLONG_ASPECT_TOLERANCE:
                raise ValueError(f"{where}: a {width}x{height} image is neither a lat-long map "
                                 f"(2:1) nor a horizontal cube cross (4:3); its aspect is "
                                 f"{width / height:g}:1")
            if off > 0:
                warnings.warn(f"{where}: {width}x{height} is not quite 2:1 ({100 * off:g}% off); "
                              "read as a lat-long map, its texels stretched to the sphere")
        self._map = torch.from_numpy(np.ascontiguousarray(rgb)).to(self.device)

    # -- integration ----------------------------------------------------------
    def integrate(self, lattice, rotations):
        """The map under each rotation [B, 3, 3] integrated onto the lattice:
        [B, l, 3] float64 (integral over texel j of L(R^T w) dw)."""
        rotations = rotations.to(device=self.device, dtype=_F64)
        batch = rotations.shape[0]
        if self._constant is not None:
            values = lattice.solid_angles[:, None] * self._constant
            return values.expand(batch, lattice.size, 3).clone()
        out = torch.zeros(batch * lattice.size, 3, dtype=_F64, device=self.device)
        if self._sky:
            omega, w = self._cells(lattice, lambda: lattice.texel_cells(contract.SKY_SUB_CELLS))
            # R^T w for each rotation: the map's radiance where texel cells look.
            sky = self._sky_radiance(torch.einsum("bji,tcj->btci", rotations, w))
            out += (omega[..., None] * sky).sum(dim=2).reshape(-1, 3)
        if self._sun is not None:
            self._sun.integrate(lattice, rotations, out)
        if self._map is not None:
            made = latlong_cells if not self._cross else cross_cells
            directions, values = self._cells(lattice, lambda: made(self._map, lattice))
            add_cells(directions, values, lattice, rotations, out)
        return out.view(batch, lattice.size, 3)

    def compiled(self):
        """The compiled part's Environment of the same spec (its integration
        is the same, and about fifteen times faster on the CPU), or None
        where the compiled part did not load, the map was given as an array,
        or in a DataLoader worker (compiled_part)."""
        core = compiled_part()
        if self.spec is None or core is None:
            return None
        if "compiled" not in self._cached:
            self._cached["compiled"] = core.Environment(self.spec)
        return self._cached["compiled"]

    def _cells(self, lattice, make):
        """What integrating onto a lattice of this resolution needs and no
        rotation changes, made once."""
        if lattice.resolution not in self._cached:
            self._cached[lattice.resolution] = make()
        return self._cached[lattice.resolution]

    def radiance(self, d):
        """Radiance of the unrotated map toward directions d [..., 3]: [..., 3]."""
        d = d.to(device=self.device, dtype=_F64)
        d = d / d.norm(dim=-1, keepdim=True)
        if self._constant is not None:
            return self._constant.expand(d.shape).clone()
        if self._map is not None:
            return (cross_radiance if self._cross else latlong_radiance)(self._map, d)
        sun = self._sun.radiance(d)
        if not self._sky:
            return sun
        return torch.where((sun.amax(dim=-1, keepdim=True) > 0), sun, self._sky_radiance(d))

    def _sky_radiance(self, d):
        """docs/lighting.md, "The built-in `sky`", without its sun disc."""
        def rgb(v):
            return torch.tensor(v, dtype=_F64, device=self.device)

        zenith, horizon = rgb(contract.SKY_ZENITH), rgb(contract.SKY_HORIZON)
        ground = rgb(contract.SKY_GROUND)
        y = d[..., 1:2]
        t = (1 - y) ** contract.SKY_HORIZON_POWER
        glow = contract.SKY_GLOW_STRENGTH * torch.exp(
            -contract.SKY_GLOW_SHARPNESS * (1 - d @ self._sky_sun))[..., None]
        sky = (1 - t) * zenith + t * horizon + glow * rgb(contract.SKY_GLOW_COLOUR)
        return torch.where(y < 0, ground.expand(sky.shape), sky)

    def __repr__(self):
        return f"<adaptive_cpca.torch.Environment {self.name}>"


class _Sun:
    """A disc of uniform radiance; its energy radiance x 2 pi (1 - cos(size/2))
    split over equal-solid-angle samples, each added to the texel holding it."""

    def __init__(self, theta, phi, size, rgb, device):
        self.size = size
        self.centre = direction_from_angles(math.radians(theta), math.radians(phi))
        self.cos_half = math.cos(0.5 * math.radians(size))
        self.rgb = torch.tensor(rgb, dtype=_F64, device=device)
        self.device = device

    def integrate(self, lattice, rotations, out):
        """Adds each rotation's disc to out [B l, 3]."""
        texel_angle = 0.5 * math.pi / lattice.resolution
        rings = min(contract.MAX_DISC_RINGS,
                    max(contract.MIN_DISC_RINGS,
                        math.ceil(contract.DISC_RINGS_PER_TEXEL * math.radians(self.size) /
                                  texel_angle)))
        segments = 2 * rings
        axis = rotations @ torch.tensor(self.centre, dtype=_F64, device=self.device)  # [B, 3]
        y_helper = (axis[:, 1].abs() < 0.9)[:, None]
        helper = torch.where(y_helper, torch.tensor([0.0, 1.0, 0.0], dtype=_F64,
                                                    device=self.device),
                             torch.tensor([1.0, 0.0, 0.0], dtype=_F64, device=self.device))
        u = torch.linalg.cross(axis, helper)
        u = u / u.norm(dim=-1, keepdim=True)
        v = torch.linalg.cross(axis, u)
        r = torch.arange(rings, device=self.device, dtype=_F64)[:, None]
        s = torch.arange(segments, device=self.device, dtype=_F64)[None, :]
        cos_t = 1 - (r + 0.5) / rings * (1 - self.cos_half)
        sin_t = torch.sqrt(torch.clamp(1 - cos_t * cos_t, min=0))
        phi = 2 * math.pi * (s + 0.5 * (r.long() & 1).to(_F64)) / segments
        around = torch.cos(phi)[None, ..., None] * u[:, None, None] + \
            torch.sin(phi)[None, ..., None] * v[:, None, None]
        w = cos_t[None, ..., None] * axis[:, None, None] + sin_t[None, ..., None] * around
        share = self.rgb * (2 * math.pi * (1 - self.cos_half)) / (rings * segments)
        batch = rotations.shape[0]
        first = (torch.arange(batch, device=self.device) * lattice.size)[:, None, None]
        texels = (lattice.texel_of(w) + first).reshape(-1)
        out.index_add_(0, texels, share.expand(texels.numel(), 3))

    def radiance(self, d):
        centre = torch.tensor(self.centre, dtype=_F64, device=self.device)
        inside = (d @ centre >= self.cos_half)[..., None]
        return torch.where(inside, self.rgb.expand(d.shape), torch.zeros_like(d))


