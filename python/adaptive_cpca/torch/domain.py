"""A file's lighting domain in PyTorch: its cube lattice's texels, or a
captured light set's cells (docs/formats.md, "Captured transport"), with the
sh9 labels of lightings on it (docs/formats.md, "Batch manifest").

A light set's cells are found as transport/light_set.h finds them: every
texel of a fine cube lattice, split into parts of exact solid angle, goes to
the nearest light (largest cosine, ties to the lower index) when that light
is within the cap; a map is integrated exactly onto the fine lattice and each
texel's integral shared out among the cells by those parts.
"""

import math

import torch

from .. import _contract as contract
from .._compiled import compiled_part
from .lattice import CubeLattice

__all__ = ["LightingDomain", "real_sh9", "texel_sh9_means"]

_F64 = torch.float64
# Part-light cosines computed at once: bounds the float64 block in memory.
_CHUNK_COSINES = 1 << 24


def real_sh9(d):
    """Real orthonormal spherical harmonics of bands 0-2 at unit directions d
    [..., 3]: [..., 9], ordered (0,0), (1,-1), (1,0), (1,1), (2,-2) .. (2,2),
    in world axes (+Y up): Y(1,-1) ~ y, Y(1,0) ~ z, Y(1,1) ~ x."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    c0, c1, c2, c3, c4 = contract.SH9_NORMALISATIONS
    return torch.stack([torch.full_like(x, c0), c1 * y, c1 * z, c1 * x, c2 * x * y, c2 * y * z,
                        c3 * (3 * z * z - 1), c2 * x * z, c4 * (x * x - y * y)], dim=-1)


def texel_sh9_means(lattice):
    """Per texel the mean of each Y over it [l, 9] (16 x 16 exact-area cells
    a texel): from the compiled part's ShProjector where it loads, else
    computed here (pure_texel_sh9_means)."""
    core = compiled_part(starts_threads=False)
    if core is None:
        return pure_texel_sh9_means(lattice)
    return torch.from_numpy(core.texel_sh9_means(lattice.resolution)).to(lattice.device)


def pure_texel_sh9_means(lattice):
    omega, centres = lattice.texel_cells(16)
    return (omega[..., None] * real_sh9(centres)).sum(1) / omega.sum(1, keepdim=True)


def cell_lattice_resolution(lights):
    """transport/light_set.h's cellLatticeResolution."""
    r = math.ceil(math.pi * math.sqrt(max(1, lights)))
    step = contract.CELL_LATTICE_STEP
    return min(contract.MAX_CELL_LATTICE,
               max(contract.MIN_CELL_LATTICE, (r + step - 1) // step * step))


class LightingDomain:
    """Texels of a 6 x R x R lattice (cubemap R), or the cells of a light set
    given its light directions [l, 3], `light_cells` ('capped-voronoi' or
    'given'), the cap in degrees and, for given cells, their solid angles."""

    def __init__(self, device, cubemap=0, directions=None, cells="capped-voronoi",
                 cap_degrees=180.0, solid_angles=None):
        self.device = torch.device(device)
        if cubemap:
            self.lattice = CubeLattice(cubemap, self.device)
            self.size = self.lattice.size
            self._texel, self._cell, self._fraction = None, None, None
            return
        directions = torch.as_tensor(directions, dtype=_F64).to(self.device)
        self.size = directions.shape[0]
        self.lattice = CubeLattice(cell_lattice_resolution(self.size), self.device)
        given = cells == "given"
        self._share_out(directions, 180.0 if given else float(cap_degrees))
        voronoi = self.gather(self.lattice.solid_angles[:, None])[:, 0]
        self._scale = torch.ones(self.size, dtype=_F64, device=self.device)
        self.cell_solid_angles = voronoi
        if given:
            given_angles = torch.as_tensor(solid_angles, dtype=_F64).to(self.device)
            self._scale = torch.where(voronoi > 0, given_angles / voronoi.clamp(min=1e-300),
                                      torch.zeros_like(voronoi))
            self.cell_solid_angles = given_angles

    @property
    def is_light_set(self):
        return self._cell is not None

    def _share_out(self, directions, cap_degrees):
        """Per (texel, cell) pair the fraction of the texel's solid angle the cell holds."""
        r = self.lattice.resolution
        sub = max(1, (contract.CELL_SAMPLES_PER_FACE_SIDE + r - 1) // r)
        cap_cosine = -2.0 if cap_degrees <= 0 or cap_degrees >= 180 else math.cos(
            math.radians(cap_degrees))
        omega, centres = self.lattice.texel_cells(sub)  # [l_fine, sub^2]
        fraction = (omega / self.lattice.solid_angles[:, None]).reshape(-1)
        centres = centres.reshape(-1, 3)
        nearest = torch.empty(centres.shape[0], dtype=torch.long, device=self.device)
        chunk = max(1 << 8, _CHUNK_COSINES // self.size)
        for first in range(0, centres.shape[0], chunk):
            cosine = centres[first:first + chunk] @ directions.t()
            best, index = cosine.max(dim=1)  # first of equal maxima: the lower index
            nearest[first:first + chunk] = torch.where(best >= cap_cosine, index,
                                                       torch.full_like(index, -1))
        texel = torch.arange(self.lattice.size, device=self.device).repeat_interleave(sub * sub)
        held = nearest >= 0
        key = texel[held] * self.size + nearest[held]
        pairs, inverse = torch.unique(key, return_inverse=True)
        self._fraction = torch.zeros(pairs.numel(), dtype=_F64, device=self.device)
        self._fraction.index_add_(0, inverse, fraction[held])
        self._texel, self._cell = pairs // self.size, pairs % self.size

    def gather(self, values):
        """Per-texel values of the fine lattice [..., l_fine, C] summed onto
        the cells: [..., l, C]."""
        shape = values.shape[:-2]
        values = values.reshape(-1, *values.shape[-2:])
        out = torch.zeros(values.shape[0], self.size, values.shape[-1], dtype=_F64,
                          device=self.device)
        out.index_add_(1, self._cell, self._fraction[None, :, None] * values[:, self._texel])
        return out.reshape(*shape, self.size, values.shape[-1])

    def integrate(self, environment, rotations):
        """The environment under each rotation [B, 3, 3] on the domain: [B,
        l, 3] float64 (a light set's cells each hold the map's integral over
        the cell)."""
        fine = environment.integrate(self.lattice, rotations)
        if not self.is_light_set:
            return fine
        return self.gather(fine) * self._scale[:, None]

    def sh9_means(self):
        """Per column the mean of each Y over it [l, 9] (16 x 16 exact-area
        cells a texel; a cell's mean from its texels' by the solid angle each
        gives it)."""
        if getattr(self, "_mean_y", None) is not None:
            return self._mean_y
        mean = texel_sh9_means(self.lattice)
        if self.is_light_set:
            weight = self._fraction * self.lattice.solid_angles[self._texel]
            sums = torch.zeros(self.size, 9, dtype=_F64, device=self.device)
            sums.index_add_(0, self._cell, weight[:, None] * mean[self._texel])
            area = torch.zeros(self.size, dtype=_F64, device=self.device)
            area.index_add_(0, self._cell, weight)
            mean = torch.where(area[:, None] > 0, sums / area.clamp(min=1e-300)[:, None],
                               torch.zeros_like(sums))
        self._mean_y = mean
        return mean
