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

from .image_reading import read_image

__all__ = ["CubeLattice", "Environment", "rotation_matrix", "ENVIRONMENT_GRAMMARS"]

# lighting/environment.h: kEnvironmentGrammars, kMaxNegativeShare,
# kSilentNegativeShare, kLatLongAspectTolerance (a test holds them equal).
ENVIRONMENT_GRAMMARS = "constant:V or constant:R,G,B, sun:THETA,PHI,SIZE_DEG,INTENSITY, sky"
MAX_NEGATIVE_SHARE = 0.01
SILENT_NEGATIVE_SHARE = 1e-6
LATLONG_ASPECT_TOLERANCE = 0.01
_MAX_PIXELS = 1 << 28
# Map cells handled at once: bounds the float64 directions of a chunk.
_CHUNK_CELLS = 1 << 20
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
        if not 1 <= int(resolution) <= 1024:
            raise ValueError(f"cube-map resolution {resolution} is out of range 1..1024")
        self.resolution = int(resolution)
        self.device = torch.device(device)
        cells = self.texel_cells(1)
        self.solid_angles = cells[0][:, 0]
        self.directions = cells[1][:, 0]

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
            self._sun = _Sun(35.0, 60.0, 2.0, (2000.0, 1900.0, 1700.0), self.device)
            self._sky_sun = torch.tensor(direction_from_angles(math.radians(35), math.radians(60)),
                                         dtype=_F64, device=self.device)
        elif spec.startswith("constant:"):
            v = _parse_numbers(spec[len("constant:"):], spec)
            if len(v) not in (1, 3):
                raise ValueError(f"environment {spec!r}: expected constant:V or constant:R,G,B")
            rgb = v * 3 if len(v) == 1 else v
            if min(rgb) < 0:
                raise ValueError(f"environment {spec!r}: radiance must be >= 0")
            self._constant = torch.tensor(rgb, dtype=_F64, device=self.device)
        elif spec.startswith("sun:"):
            v = _parse_numbers(spec[len("sun:"):], spec)
            if len(v) != 4:
                raise ValueError(
                    f"environment {spec!r}: expected sun:THETA,PHI,SIZE_DEG,INTENSITY")
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
        if width < 2 or height < 1 or width * height > _MAX_PIXELS:
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
            omega, w = self._cells(lattice, lambda: lattice.texel_cells(4))
            # R^T w for each rotation: the map's radiance where texel cells look.
            sky = self._sky_radiance(torch.einsum("bji,tcj->btci", rotations, w))
            out += (omega[..., None] * sky).sum(dim=2).reshape(-1, 3)
        if self._sun is not None:
            self._sun.integrate(lattice, rotations, out)
        if self._map is not None:
            made = _latlong_cells if not self._cross else _cross_cells
            directions, values = self._cells(lattice, lambda: made(self._map, lattice))
            _add_cells(directions, values, lattice, rotations, out)
        return out.view(batch, lattice.size, 3)

    def compiled(self):
        """The compiled part's Environment of the same spec (its integration
        is the same, and about fifteen times faster on the CPU), or None
        where the compiled part did not load, the map was given as an array,
        or in a DataLoader worker (in_forked_worker)."""
        if self.spec is None or self.in_forked_worker():
            return None
        if "compiled" not in self._cached:
            from . import _core
            self._cached["compiled"] = None if _core is None else _core.Environment(self.spec)
        return self._cached["compiled"]

    @staticmethod
    def in_forked_worker():
        """True in a DataLoader worker: the compiled part's thread pools (TBB,
        OpenImageIO) do not survive a fork, so nothing there may call it."""
        info = torch.utils.data.get_worker_info()
        return info is not None

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
            return (_cross_radiance if self._cross else _latlong_radiance)(self._map, d)
        sun = self._sun.radiance(d)
        if not self._sky:
            return sun
        return torch.where((sun.amax(dim=-1, keepdim=True) > 0), sun, self._sky_radiance(d))

    def _sky_radiance(self, d):
        """docs/lighting.md, "The built-in `sky`", without its sun disc."""
        zenith = torch.tensor([0.16, 0.30, 0.64], dtype=_F64, device=self.device)
        horizon = torch.tensor([0.60, 0.66, 0.76], dtype=_F64, device=self.device)
        ground = torch.tensor([0.10, 0.09, 0.08], dtype=_F64, device=self.device)
        y = d[..., 1:2]
        t = (1 - y) ** 4
        glow = 0.5 * torch.exp(-40 * (1 - d @ self._sky_sun))[..., None]
        glow_colour = torch.tensor([1.0, 0.9, 0.7], dtype=_F64, device=self.device)
        sky = (1 - t) * zenith + t * horizon + glow * glow_colour
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
        rings = min(512, max(8, math.ceil(16 * math.radians(self.size) / texel_angle)))
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


def _latlong_cells(rgb, lattice):
    """A lat-long map's sub-cells: each pixel over its exact solid angle
    ((cos t0 - cos t1) dphi) split into sub-cells at most 1/8 of a texel
    across; their unrotated centre directions [n, 3] and radiance x solid
    angle [n, 3], cells of black pixels left out."""
    height, width = rgb.shape[:2]
    device = rgb.device
    texel_angle = 0.5 * math.pi / lattice.resolution
    sub = max(1, math.ceil(8 * (math.pi / height) / texel_angle))
    sub_w, sub_h = width * sub, height * sub
    i = torch.arange(sub_w, device=device, dtype=_F64)
    phi = 2 * math.pi * ((i + 0.5) / sub_w - 0.5)  # u = 0.5 + phi / 2 pi
    sin_phi, cos_phi = torch.sin(phi), torch.cos(phi)
    d_phi = 2 * math.pi / sub_w
    column_pixel = torch.arange(sub_w, device=device) // sub
    directions, values = [], []
    chunk = max(1, _CHUNK_CELLS // sub_w)
    for first in range(0, sub_h, chunk):
        r = torch.arange(first, min(sub_h, first + chunk), device=device, dtype=_F64)
        theta0, theta1 = math.pi * r / sub_h, math.pi * (r + 1) / sub_h
        omega = (torch.cos(theta0) - torch.cos(theta1)) * d_phi
        theta = 0.5 * (theta0 + theta1)
        sin_t, cos_t = torch.sin(theta)[:, None], torch.cos(theta)[:, None]
        d = torch.stack([sin_t * sin_phi, cos_t.expand(-1, sub_w), -sin_t * cos_phi], dim=-1)
        rows = rgb[r.long() // sub]  # [rows, W, 3]
        pixels = (rows if sub == 1 else rows[:, column_pixel]).to(_F64)
        lit = (pixels != 0).any(dim=-1)
        directions.append(d[lit])
        values.append((pixels * omega[:, None, None])[lit])
    return torch.cat(directions), torch.cat(values)


def _add_cells(directions, values, lattice, rotations, out):
    """Each cell's value added, for each rotation b, to the texel holding R_b
    d: out [B l, 3]."""
    batch = rotations.shape[0]
    chunk = max(1, _CHUNK_CELLS // batch)
    first_texel = (torch.arange(batch, device=out.device) * lattice.size)[:, None]
    for first in range(0, directions.shape[0], chunk):
        d = directions[first:first + chunk]
        texels = lattice.texel_of(torch.einsum("bij,nj->bni", rotations, d)) + first_texel
        v = values[first:first + chunk]
        out.index_add_(0, texels.reshape(-1), v.expand(batch, -1, 3).reshape(-1, 3))


# lighting/cube_cross.h: the cross's faces (column, row, centre, right, down).
_CROSS_FACES = (
    (0, 1, (-1, 0, 0), (0, 0, -1), (0, -1, 0)),
    (1, 1, (0, 0, -1), (1, 0, 0), (0, -1, 0)),
    (2, 1, (1, 0, 0), (0, 0, 1), (0, -1, 0)),
    (3, 1, (0, 0, 1), (-1, 0, 0), (0, -1, 0)),
    (1, 0, (0, 1, 0), (1, 0, 0), (0, 0, -1)),
    (1, 2, (0, -1, 0), (1, 0, 0), (0, 0, 1)),
)


def _cross_cells(rgb, lattice):
    """A cube cross's sub-cells: each pixel constant over its exact solid
    angle on its face, split into sub-cells at most 1/8 of a texel across;
    centre directions [n, 3] and radiance x solid angle [n, 3]."""
    face_size = rgb.shape[0] // 3
    device = rgb.device
    sub = max(1, (8 * lattice.resolution + face_size - 1) // face_size)
    cells = face_size * sub
    cell = 2.0 / cells
    k = torch.arange(cells, device=device)
    a0 = -1 + k.to(_F64) * cell
    omega = rectangle_solid_angle(a0[None, :], a0[:, None], a0[None, :] + cell,
                                  a0[:, None] + cell)  # [j (down), i (right)]
    directions, values = [], []
    for column, row, centre, right, down in _CROSS_FACES:
        c, rt, dn = (torch.tensor(v, dtype=_F64, device=device) for v in (centre, right, down))
        w = (c + (a0[None, :, None] + 0.5 * cell) * rt + (a0[:, None, None] + 0.5 * cell) * dn)
        face = rgb[row * face_size:(row + 1) * face_size, column * face_size:(column + 1) * face_size]
        pixels = face[k // sub][:, k // sub].to(_F64)
        lit = (pixels != 0).any(dim=-1)
        directions.append((w / w.norm(dim=-1, keepdim=True))[lit])
        values.append((pixels * omega[..., None])[lit])
    return torch.cat(directions), torch.cat(values)


def _latlong_radiance(rgb, d):
    """Bilinear between pixel centres, wrapping in u and clamping in v."""
    height, width = rgb.shape[:2]
    u = 0.5 + torch.atan2(d[..., 0], -d[..., 2]) / (2 * math.pi)
    v = torch.acos(d[..., 1].clamp(-1, 1)) / math.pi
    x = u * width - 0.5
    y = (v * height - 0.5).clamp(0, height - 1)
    x0, y0 = torch.floor(x), torch.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    x0, y0 = x0.long(), y0.long()
    total = torch.zeros(d.shape, dtype=_F64, device=d.device)
    for dy in (0, 1):
        for dx in (0, 1):
            px = torch.remainder(x0 + dx, width)
            py = torch.clamp(y0 + dy, max=height - 1)
            weight = (fx if dx else 1 - fx) * (fy if dy else 1 - fy)
            total += weight * rgb[py, px].to(_F64)
    return total


def _cross_radiance(rgb, d):
    """The nearest cross pixel."""
    face_size = rgb.shape[0] // 3
    centres = torch.tensor([f[2] for f in _CROSS_FACES], dtype=_F64, device=d.device)
    best = torch.argmax(d @ centres.t(), dim=-1)
    faces = torch.tensor([[f[0], f[1]] for f in _CROSS_FACES], device=d.device)
    right = torch.tensor([f[3] for f in _CROSS_FACES], dtype=_F64, device=d.device)[best]
    down = torch.tensor([f[4] for f in _CROSS_FACES], dtype=_F64, device=d.device)[best]
    on_face = d / (d * centres[best]).sum(-1, keepdim=True)

    def pixel(t):
        return torch.floor((t + 1) / 2 * face_size).clamp(0, face_size - 1).long()

    x = faces[best, 0] * face_size + pixel((on_face * right).sum(-1))
    y = faces[best, 1] * face_size + pixel((on_face * down).sum(-1))
    return rgb[y, x].to(_F64)
