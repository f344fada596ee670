"""The cube lattice and rotations in PyTorch (docs/lighting.md, "Conventions").

The lattice's texel directions and exact solid angles come from the compiled
part where it loads (transport/cube_lattice.h), else from the same
arithmetic here; sub-cells and the texel of a direction are computed on the
lattice's device, as maps are integrated there.
"""

import math

import numpy as np
import torch

from .._compiled import compiled_part
from .._contract import MAX_CUBE_RESOLUTION

__all__ = ["CubeLattice", "rotation_matrix", "direction_from_angles", "rectangle_solid_angle"]

_F64 = torch.float64


def rotation_matrix(yaw=0.0, pitch=0.0, roll=0.0, device="cpu"):
    """R = Rz(roll) Rx(pitch) Ry(yaw), degrees, float64 [3, 3]; given
    sequences (or 1-D tensors) of angles, one for each: [B, 3, 3]."""
    angles = [np.atleast_1d(np.asarray(torch.as_tensor(a).cpu(), dtype=np.float64))
              for a in (yaw, pitch, roll)]
    batched = any(np.ndim(a) > 0 and not (torch.is_tensor(a) and a.dim() == 0)
                  for a in (yaw, pitch, roll))
    y, p, r = np.broadcast_arrays(*angles)
    for name, values in (("yaw", y), ("pitch", p), ("roll", r)):
        if not np.isfinite(values).all():
            raise ValueError(f"{name} {values[~np.isfinite(values)][0]}: not a finite number "
                             "of degrees")
    y, p, r = np.radians(y), np.radians(p), np.radians(r)
    zero, one = np.zeros_like(y), np.ones_like(y)
    ry = np.stack([np.stack([np.cos(y), zero, np.sin(y)], -1), np.stack([zero, one, zero], -1),
                   np.stack([-np.sin(y), zero, np.cos(y)], -1)], -2)
    rx = np.stack([np.stack([one, zero, zero], -1), np.stack([zero, np.cos(p), -np.sin(p)], -1),
                   np.stack([zero, np.sin(p), np.cos(p)], -1)], -2)
    rz = np.stack([np.stack([np.cos(r), -np.sin(r), zero], -1),
                   np.stack([np.sin(r), np.cos(r), zero], -1), np.stack([zero, zero, one], -1)], -2)
    m = torch.tensor(rz @ rx @ ry, dtype=_F64, device=device)
    return m if batched else m[0]


def direction_from_angles(theta, phi):
    """Lat-long angles (radians; theta from +Y, phi 0 towards -Z, 90 deg towards +X)."""
    return np.array([math.sin(theta) * math.sin(phi), math.cos(theta),
                     -math.sin(theta) * math.cos(phi)])


def _corner_area(x, y):
    return torch.atan2(x * y, torch.sqrt(x * x + y * y + 1))


def rectangle_solid_angle(x0, y0, x1, y1):
    """Exact solid angle of the face-plane rectangle [x0, x1] x [y0, y1] (unit cube)."""
    return _corner_area(x1, y1) - _corner_area(x0, y1) - _corner_area(x1, y0) + _corner_area(x0, y0)


class CubeLattice:
    """The 6 x R x R lattice (docs/lighting.md): faces +X, -X, +Y, -Y, +Z, -Z,
    the OpenGL (s, t) table, texel j = face R^2 + row R + col."""

    def __init__(self, resolution, device="cpu"):
        if not 1 <= int(resolution) <= MAX_CUBE_RESOLUTION:
            raise ValueError(f"cube-map resolution {resolution} is out of range "
                             f"1..{MAX_CUBE_RESOLUTION}")
        self.resolution = int(resolution)
        self.device = torch.device(device)
        core = compiled_part(starts_threads=False)
        if core is not None:
            directions, solid_angles = core.cube_lattice(self.resolution)
            self.directions = torch.from_numpy(directions).to(self.device)
            self.solid_angles = torch.from_numpy(solid_angles).to(self.device)
        else:
            self.solid_angles, self.directions = self.pure_texels()

    def pure_texels(self):
        """The texels' exact solid angles [l] and centre directions [l, 3]
        computed here (what the compiled part gives where it loads)."""
        omega, w = self.texel_cells(1)
        return omega[:, 0], w[:, 0]

    @property
    def size(self):
        return 6 * self.resolution ** 2

    @staticmethod
    def face_direction(face, sc, tc):
        """Unnormalised directions of face coordinates (face a tensor of 0..5)."""
        one = torch.ones_like(sc)
        table = [  # (x, y, z) per face, the inverse of the OpenGL table
            (one, -tc, -sc), (-one, -tc, sc), (sc, one, tc),
            (sc, -one, -tc), (sc, -tc, one), (-sc, -tc, -one)]
        out = torch.empty(sc.shape + (3,), dtype=sc.dtype, device=sc.device)
        for f, xyz in enumerate(table):
            chosen = face == f
            for axis in range(3):
                out[..., axis] = torch.where(chosen, xyz[axis], out[..., axis])
        return out

    def texel_of(self, d):
        """The texel holding each direction d [..., 3] (texelOf's arithmetic)."""
        x, y, z = d[..., 0], d[..., 1], d[..., 2]
        ax, ay, az = x.abs(), y.abs(), z.abs()
        x_major = (ax >= ay) & (ax >= az)
        y_major = ~x_major & (ay >= az)
        ma = torch.where(x_major, ax, torch.where(y_major, ay, az))
        face = torch.where(x_major, torch.where(x >= 0, 0, 1),
                           torch.where(y_major, torch.where(y >= 0, 2, 3),
                                       torch.where(z >= 0, 4, 5)))
        sc = torch.where(x_major, torch.where(x >= 0, -z, z),
                         torch.where(y_major, x, torch.where(z >= 0, x, -x)))
        tc = torch.where(y_major, torch.where(y >= 0, z, -z), -y)
        if not bool(((ma > 0) & torch.isfinite(ma)).all()):
            raise ValueError("a direction without a major axis (zero or not finite)")
        r = self.resolution
        row = torch.floor((tc / ma + 1) * 0.5 * r).clamp(0, r - 1).long()
        col = torch.floor((sc / ma + 1) * 0.5 * r).clamp(0, r - 1).long()
        return (face.long() * r + row) * r + col

    def texel_cells(self, sub):
        """Each texel split into sub x sub cells: their exact solid angles
        [l, sub^2] and normalised centre directions [l, sub^2, 3], cells in
        (a, b) order (a along t, b along s)."""
        r = self.resolution
        step, cell = 2.0 / r, 2.0 / r / sub
        texel = torch.arange(self.size, device=self.device)
        face, row, col = texel // (r * r), (texel % (r * r)) // r, texel % r
        k = torch.arange(sub * sub, device=self.device)
        a, b = k // sub, k % sub
        s0 = -1 + col[:, None].to(_F64) * step + b[None, :].to(_F64) * cell
        t0 = -1 + row[:, None].to(_F64) * step + a[None, :].to(_F64) * cell
        omega = rectangle_solid_angle(s0, t0, s0 + cell, t0 + cell)
        w = self.face_direction(face[:, None].expand_as(s0), s0 + 0.5 * cell, t0 + 0.5 * cell)
        return omega, w / w.norm(dim=-1, keepdim=True)
