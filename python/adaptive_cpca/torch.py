"""Relighting in PyTorch: a model file held on any torch device.

Pure Python over PyTorch and h5py (no compiled part), reading model files
exactly as docs/formats.md ("Model file") documents them, so it runs where
the compiled module was not built for the Python at hand (a GPU machine's).
Works on torch 1.13 (Debian 12's) and 2.x.

    from adaptive_cpca.torch import TorchRelighter
    r = TorchRelighter("plant-model.h5", device="cuda")
    images = r.relight(lightings)   # [B, l, 3] lattice lightings -> [B, 3, H, W]

A lattice lighting holds, per column (a cube-lattice texel, or a captured
set's light), the radiance integrated over its solid angle, as the CLI and
`Relighter.lighting(env).values` make it.
"""

import h5py
import numpy as np
import torch

__all__ = ["TorchRelighter"]

# Rows relit per widened block of a cluster's coefficients: bounds the float
# copy of stored i8 or f16 coefficients (CPU torch 1.13 multiplies neither).
_BLOCK_ROWS = 65536


def _attribute(f, name, default=None):
    value = f.attrs.get(name, default)
    if isinstance(value, bytes):
        value = value.decode()
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value.item()
    return value


class TorchRelighter:
    """A model file on a torch device, relighting batches of lattice lightings.

    The model stays at its stored precision on the device (i8 and f16
    coefficients and bases are widened block by block in the arithmetic) and
    relights as docs/formats.md defines it: row p of cluster c under L is
    albedo_p (u_p . W_c^T V_g^T L + mean_c . V_g^T L), composed over the
    background as `coverage * relit`.
    """

    def __init__(self, path, device="cpu"):
        self.path = str(path)
        self.device = torch.device(device)
        with h5py.File(self.path, "r") as f:
            if _attribute(f, "format") != "adaptive-cpca model":
                raise ValueError(f"{self.path}: not an adaptive-cpca model file "
                                 f"(format {_attribute(f, 'format')!r}); a transport relights "
                                 "through adaptive_cpca.open")
            if int(_attribute(f, "complete", 0)) != 1:
                raise ValueError(f"{self.path}: incomplete model file (no complete = 1)")
            version = int(_attribute(f, "version"))
            if version < 2:
                raise ValueError(f"{self.path}: model version {version} is no longer read; "
                                 "run compress (or build) again")
            self._read(f)

    def _tensor(self, array, dtype=None):
        t = torch.from_numpy(np.ascontiguousarray(array))
        if dtype is not None:
            t = t.to(dtype)
        return t.to(self.device)

    def _read(self, f):
        self.width = int(_attribute(f, "width"))
        self.height = int(_attribute(f, "height"))
        self.method = _attribute(f, "method")
        self.channels = int(_attribute(f, "channels", 1))
        self.coefficient_precision = _attribute(f, "coeffs", "f32")
        self.basis_precision = _attribute(f, "bases", "f32")
        self.has_mean = bool(int(_attribute(f, "has_mean", 0)))
        basis = f["global_basis"][:]
        self.global_bases = basis.shape[1]
        self.lattice_size = basis.shape[0] // self.channels
        self.rows = int(_attribute(f, "occupied_pixels"))
        # [w, N] float32: the projection V_g^T L is one product a batch.
        self.global_basis = self._tensor(basis, torch.float32)
        self.pixels = self._tensor(f["pixels"][:].astype(np.int64))
        self.albedo = self._tensor(f["albedo"][:], torch.float32)
        self.coverage = self._tensor(f["coverage"][:], torch.float32)
        self.cluster_rows = self._tensor(f["cluster_rows"][:].astype(np.int64))
        self.row_offsets = f["cluster_row_offsets"][:].astype(np.int64)
        self.ranks = f["cluster_rank"][:].astype(np.int64)
        self.basis_offsets = f["cluster_basis_offsets"][:].astype(np.int64)
        self.coefficient_offsets = f["coefficient_offsets"][:].astype(np.int64)
        # Stored precision kept: float16 and int8 stay so in memory.
        self.bases = self._tensor(f["bases"][:])
        self.means = self._tensor(f["means"][:])
        self.coefficients = self._tensor(f["coefficients"][:])
        self.coefficient_scale = self._tensor(f["coefficient_scale"][:], torch.float32)
        self.first_basis = np.concatenate([[0], np.cumsum(self.ranks)])

    @property
    def clusters(self):
        return len(self.ranks)

    def _projected(self, lightings):
        """V_g^T L for each lighting: [B, N, 3] (RGB rows: channel c's block)."""
        l = self.lattice_size
        if self.channels == 1:
            return torch.einsum("wn,bwc->bnc", self.global_basis, lightings)
        return torch.stack([self.global_basis[c * l:(c + 1) * l].t() @ lightings[:, :, c].t()
                            for c in range(3)], dim=2).permute(1, 0, 2)

    def relit_rows(self, lightings):
        """Each row's relit RGB (albedo applied), [B, P, 3], before composition."""
        lightings = self._lightings(lightings)
        batch, n = lightings.shape[0], self.global_bases
        projected = self._projected(lightings).reshape(batch, n, 3)
        flat = projected.permute(1, 0, 2).reshape(n, batch * 3)  # [N, 3B]
        out = torch.zeros(self.rows, batch * 3, dtype=torch.float32, device=self.device)
        for c in range(self.clusters):
            self._relight_cluster(c, flat, out)
        out = out.reshape(self.rows, batch, 3).permute(1, 0, 2)
        return out * self.albedo.unsqueeze(0)

    def _relight_cluster(self, c, flat, out):
        n, rank = self.global_bases, int(self.ranks[c])
        first, last = int(self.row_offsets[c]), int(self.row_offsets[c + 1])
        if last == first:
            return
        # W_c^T (V_g^T L): [n_c, 3B]; the mean's term [3B].
        # W_c is N x n_c column-major: its rows as stored are W_c^T.
        wt = self.bases[int(self.basis_offsets[c]):int(self.basis_offsets[c + 1])]
        towards = wt.to(torch.float32).reshape(rank, n) @ flat if rank else None
        mean = self.means[c * n:(c + 1) * n].to(torch.float32) @ flat if self.has_mean else None
        scale = self.coefficient_scale[int(self.first_basis[c]):int(self.first_basis[c + 1])]
        offset = int(self.coefficient_offsets[c])
        for start in range(first, last, _BLOCK_ROWS):
            stop = min(last, start + _BLOCK_ROWS)
            value = torch.zeros(stop - start, flat.shape[1], device=self.device)
            if rank:
                u = self.coefficients[offset + (start - first) * rank:
                                      offset + (stop - first) * rank]
                u = u.to(torch.float32).reshape(stop - start, rank) * scale
                value = u @ towards
            if mean is not None:
                value = value + mean
            out[self.cluster_rows[start:stop]] = value

    def _lightings(self, lightings):
        lightings = torch.as_tensor(lightings, dtype=torch.float32, device=self.device)
        if lightings.dim() == 2:
            lightings = lightings.unsqueeze(0)
        if lightings.dim() != 3 or lightings.shape[1:] != (self.lattice_size, 3):
            raise ValueError(f"lightings of shape {tuple(lightings.shape)}: this model takes "
                             f"[B, {self.lattice_size}, 3] (or [{self.lattice_size}, 3])")
        if not torch.isfinite(lightings).all():
            raise ValueError("lightings hold values that are not finite")
        return lightings

    def relight(self, lightings, background="black", keep_negative=False, layout="chw"):
        """Images of a batch of lattice lightings [B, l, 3] (or one, [l, 3]).

        background: 'black' (3 channels) or 'alpha' (4, the fourth each
        pixel's coverage). Values below zero (a model's reconstruction can
        undershoot) are clamped to 0 unless keep_negative, as the CLI does.
        layout: 'chw' gives [B, C, H, W], 'hwc' gives [B, H, W, C].
        """
        if background not in ("black", "alpha"):
            raise ValueError(f"background {background!r}: 'black' or 'alpha' (an environment "
                             "behind the subject comes with the lighting work of this module)")
        if layout not in ("chw", "hwc"):
            raise ValueError(f"layout {layout!r}: 'chw' or 'hwc'")
        rows = self.relit_rows(lightings) * self.coverage[None, :, None]
        if not keep_negative:
            rows = rows.clamp_min(0)
        batch = rows.shape[0]
        channels = 4 if background == "alpha" else 3
        image = torch.zeros(batch, self.height * self.width, channels, device=self.device)
        image[:, self.pixels, :3] = rows
        if background == "alpha":
            alpha = torch.zeros(self.height * self.width, device=self.device)
            alpha[self.pixels] = self.coverage
            image[:, :, 3] = alpha
        image = image.reshape(batch, self.height, self.width, channels)
        return image if layout == "hwc" else image.permute(0, 3, 1, 2).contiguous()
