"""A map file's pixels as cells for the lattice, in PyTorch.

Each pixel is constant over its exact solid angle (lat-long: (cos t0 - cos
t1) dphi; a cube cross: the rectangle on its face), split into sub-cells at
most 1/MAP_SUB_CELLS_PER_TEXEL of a texel across, as lighting/ splits them;
each cell is added to the texel holding its rotated centre.
"""

import math

import torch

from .._contract import CROSS_FACES, MAP_SUB_CELLS_PER_TEXEL
from .lattice import rectangle_solid_angle

__all__ = ["latlong_cells", "cross_cells", "add_cells", "latlong_radiance", "cross_radiance"]

_F64 = torch.float64
# Map cells handled at once: bounds the float64 directions of a chunk.
_CHUNK_CELLS = 1 << 20


def latlong_cells(rgb, lattice):
    """A lat-long map's sub-cells: each pixel over its exact solid angle
    ((cos t0 - cos t1) dphi) split into sub-cells at most 1/8 of a texel
    across; their unrotated centre directions [n, 3] and radiance x solid
    angle [n, 3], cells of black pixels left out."""
    height, width = rgb.shape[:2]
    device = rgb.device
    texel_angle = 0.5 * math.pi / lattice.resolution
    sub = max(1, math.ceil(MAP_SUB_CELLS_PER_TEXEL * (math.pi / height) / texel_angle))
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


def add_cells(directions, values, lattice, rotations, out):
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


def cross_cells(rgb, lattice):
    """A cube cross's sub-cells: each pixel constant over its exact solid
    angle on its face, split into sub-cells at most 1/8 of a texel across;
    centre directions [n, 3] and radiance x solid angle [n, 3]."""
    face_size = rgb.shape[0] // 3
    device = rgb.device
    sub = max(1, (MAP_SUB_CELLS_PER_TEXEL * lattice.resolution + face_size - 1) // face_size)
    cells = face_size * sub
    cell = 2.0 / cells
    k = torch.arange(cells, device=device)
    a0 = -1 + k.to(_F64) * cell
    omega = rectangle_solid_angle(a0[None, :], a0[:, None], a0[None, :] + cell,
                                  a0[:, None] + cell)  # [j (down), i (right)]
    directions, values = [], []
    for column, row, centre, right, down in CROSS_FACES:
        c, rt, dn = (torch.tensor(v, dtype=_F64, device=device) for v in (centre, right, down))
        w = (c + (a0[None, :, None] + 0.5 * cell) * rt + (a0[:, None, None] + 0.5 * cell) * dn)
        face = rgb[row * face_size:(row + 1) * face_size, column * face_size:(column + 1) * face_size]
        pixels = face[k // sub][:, k // sub].to(_F64)
        lit = (pixels != 0).any(dim=-1)
        directions.append((w / w.norm(dim=-1, keepdim=True))[lit])
        values.append((pixels * omega[..., None])[lit])
    return torch.cat(directions), torch.cat(values)


def latlong_radiance(rgb, d):
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


def cross_radiance(rgb, d):
    """The nearest cross pixel."""
    face_size = rgb.shape[0] // 3
    centres = torch.tensor([f[2] for f in CROSS_FACES], dtype=_F64, device=d.device)
    best = torch.argmax(d @ centres.t(), dim=-1)
    faces = torch.tensor([[f[0], f[1]] for f in CROSS_FACES], device=d.device)
    right = torch.tensor([f[3] for f in CROSS_FACES], dtype=_F64, device=d.device)[best]
    down = torch.tensor([f[4] for f in CROSS_FACES], dtype=_F64, device=d.device)[best]
    on_face = d / (d * centres[best]).sum(-1, keepdim=True)

    def pixel(t):
        return torch.floor((t + 1) / 2 * face_size).clamp(0, face_size - 1).long()

    x = faces[best, 0] * face_size + pixel((on_face * right).sum(-1))
    y = faces[best, 1] * face_size + pixel((on_face * down).sum(-1))
    return rgb[y, x].to(_F64)
