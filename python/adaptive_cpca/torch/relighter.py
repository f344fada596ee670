"""TorchRelighter: a model file held on a torch device, relit in batches.

Pure Python over PyTorch and h5py, reading model files exactly as
docs/formats.md ("Model file") documents them; the versions it reads come
from the generated contract (adaptive_cpca._contract).
"""

import h5py
import numpy as np
import torch

from .._contract import MODEL_VERSION, OLDEST_MODEL_VERSION
from .camera import pixel_rays, transforms_fields
from .domain import LightingDomain
from .frame_fields import frame_fields
from .lighting import Environment, rotation_matrix
from .model import DeviceModel
from .sources import SourceLighting, check_sun

__all__ = ["TorchRelighter"]
# The datasets held on the device.
_HELD = ("global_basis", "pixels", "albedo", "coverage", "cluster_rows", "bases", "means",
         "coefficients", "coefficient_scale")


def _attribute(f, name, default=None):
    value = f.attrs.get(name, default)
    if isinstance(value, bytes):
        value = value.decode()
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value.item()
    return value


def _free_bytes(device):
    """Memory free on a CUDA device; None where torch cannot say (the CPU)."""
    if device.type != "cuda":
        return None
    free, _ = torch.cuda.mem_get_info(device)
    return free


class TorchRelighter:
    """A model file on a torch device, relighting batches of lattice lightings.

    The model stays at its stored precision on the device (i8 and f16
    coefficients and bases are widened block by block in the arithmetic) and
    relights as docs/formats.md defines it: row p of cluster c under L is
    albedo_p (u_p . W_c^T V_g^T L + mean_c . V_g^T L), composed over the
    background as `coverage * relit + (1 - coverage) * background`.
    """

    def __init__(self, path, device="cpu", kernel="auto", lighting="auto"):
        if lighting not in ("auto", "torch"):
            raise ValueError(f"lighting {lighting!r}: 'auto' or 'torch'")
        self.lighting_backend = lighting
        self.path = str(path)
        self.device = torch.device(device)
        with h5py.File(self.path, "r") as f:
            if _attribute(f, "format") != "adaptive-cpca model":
                raise ValueError(f"{self.path}: not an adaptive-cpca model file "
                                 f"(format {_attribute(f, 'format')!r}); a transport relights "
                                 "through adaptive_cpca.open")
            version = int(_attribute(f, "version", 0))
            if not OLDEST_MODEL_VERSION <= version <= MODEL_VERSION:
                raise ValueError(
                    f"{self.path}: model format version {version}; this reader reads "
                    f"{OLDEST_MODEL_VERSION} to {MODEL_VERSION}: " +
                    ("compress (or build) it again" if version < OLDEST_MODEL_VERSION else
                     "written by a newer adaptive-cpca"))
            if int(_attribute(f, "complete", 0)) != 1:
                raise ValueError(f"{self.path}: the model file is incomplete")
            self._require_memory(f)
            try:
                self._read(f, kernel)
            except RuntimeError as e:
                if "out of memory" not in str(e):
                    raise
                raise MemoryError(f"{self.path}: {self.device} ran out of memory holding the "
                                  f"model ({self.model_bytes / 2**30:.2f} GiB)") from None
        self._domain = None
        self._rays = None
        self._coverage = None
        self._sources = SourceLighting(self.path, self.device)

    def _require_memory(self, f):
        self.model_bytes = sum(f[name].size * f[name].dtype.itemsize for name in _HELD)
        free = _free_bytes(self.device)
        if free is not None and self.model_bytes > free:
            raise MemoryError(f"{self.path}: the model needs {self.model_bytes / 2**30:.2f} GiB "
                              f"on {self.device}, which has {free / 2**30:.2f} GiB free")

    def _tensor(self, array, dtype=None):
        t = torch.from_numpy(np.ascontiguousarray(array))
        if dtype is not None:
            t = t.to(dtype)
        return t.to(self.device)

    def _read(self, f, kernel):
        self.width = int(_attribute(f, "width"))
        self.height = int(_attribute(f, "height"))
        self.method = _attribute(f, "method")
        self.channels = int(_attribute(f, "channels", 1))
        self.cubemap = int(_attribute(f, "cubemap"))
        self.coefficient_precision = _attribute(f, "coeffs", "f32")
        self.basis_precision = _attribute(f, "bases", "f32")
        basis = f["global_basis"][:]
        self.global_bases = basis.shape[1]
        self.lattice_size = basis.shape[0] // self.channels
        self.rows = int(_attribute(f, "occupied_pixels"))
        self._read_lighting_domain(f)
        # [w, N] float32: the projection V_g^T L is one product a batch.
        self.global_basis = self._tensor(basis, torch.float32)
        # Rows held in cluster order: each cluster's block is a slice.
        order = f["cluster_rows"][:].astype(np.int64)
        self.pixels = self._tensor(f["pixels"][:].astype(np.int64)[order])
        self.albedo = self._tensor(f["albedo"][:][order], torch.float32)
        self.coverage = self._tensor(f["coverage"][:][order], torch.float32)
        self._albedo_channels = self.albedo.t().contiguous()  # [3, P]
        self.file_order = self._tensor(np.argsort(order))
        self.model = DeviceModel(f, self.path, self.device, kernel)

    def _read_lighting_domain(self, f):
        if self.cubemap:
            self.camera = {name: np.asarray(f.attrs[f"camera_{name}"], dtype=np.float64)
                           for name in ("eye", "target", "up", "fov_deg")}
            self.camera.update(transforms_fields(self.camera, self.width, self.height))
            self._light_set = None
            return
        self.camera = None
        self._light_set = {
            "directions": f["light_direction"][:], "solid_angles": f["light_solid_angle"][:],
            "cells": _attribute(f, "light_cells", "capped-voronoi"),
            "cap_degrees": float(_attribute(f, "light_cell_cap_deg", 180.0))}

    @property
    def clusters(self):
        return len(self.model.ranks)

    @property
    def is_light_set(self):
        return self.cubemap == 0

    @property
    def domain(self):
        """The file's lighting domain (lattice or light cells), made on first use."""
        if self._domain is None:
            if self._light_set is None:
                self._domain = LightingDomain(self.device, cubemap=self.cubemap)
            else:
                self._domain = LightingDomain(self.device, **self._light_set)
        return self._domain

    # -- lighting -----------------------------------------------------------
    def environment(self, env):
        """An Environment on this device: a spec (constant:, sun:, sky), an
        image file, or a map [H, W, C] (array or tensor). Load a map once and
        pass it to lighting() for every rotation."""
        return env if isinstance(env, Environment) else Environment(env, self.device)

    def lighting(self, env, yaw=0.0, pitch=0.0, roll=0.0, exposure=0.0, dtype=torch.float32):
        """The lattice lighting [l, 3] of env (as environment() takes it) under
        the rotation, times 2^exposure: per column the rotated map's radiance
        integrated over the texel (or the light's cell), made on the device
        in float64 and returned as dtype. Given sequences of angles (or
        exposures), one lighting each in one pass: [B, l, 3]."""
        stops = np.asarray(torch.as_tensor(exposure).cpu(), dtype=np.float64)
        if not np.isfinite(stops).all():
            raise ValueError(f"exposure {exposure}: not a finite number of stops")
        rotations = rotation_matrix(yaw, pitch, roll, self.device)
        one = rotations.dim() == 2 and stops.ndim == 0
        env = self.environment(env)
        compiled = self._compiled_lighting(env)
        if compiled is not None:
            angles = np.broadcast_arrays(*(np.atleast_1d(np.asarray(
                torch.as_tensor(a).cpu(), dtype=np.float64)) for a in (yaw, pitch, roll)))
            turns = list(zip(*(a.tolist() for a in angles)))
            values = torch.from_numpy(compiled.lattice_lightings(self.cubemap, turns))
        else:
            values = self.domain.integrate(env, rotations.reshape(-1, 3, 3))
        scale = torch.as_tensor(2.0 ** stops, dtype=torch.float64, device=self.device)
        values = values * scale.reshape(-1, 1, 1)
        return (values[0] if one else values).to(dtype)

    def split_lighting(self, env, yaw=0.0, pitch=0.0, roll=0.0, exposure=0.0, sun="auto",
                       dtype=torch.float32):
        """lighting() with the map's sun and bright lamps split off to be lit
        exactly (sun= as `relight --sun` takes it; adaptive_cpca.torch.sources):
        (the lattice lighting of the rest, the sources' light per row or
        None), for relight(lighting, source_light=light). Where the split
        cannot be made (no compiled part, a map given as pixels, a captured
        light set, sun='off'): (lighting(), None)."""
        check_sun(sun)
        env = self.environment(env)
        stops = np.asarray(torch.as_tensor(exposure).cpu(), dtype=np.float64)
        angles = [np.asarray(torch.as_tensor(a).cpu(), dtype=np.float64) for a in (yaw, pitch, roll)]
        one = all(a.ndim == 0 for a in angles) and stops.ndim == 0
        *angles, stops = np.broadcast_arrays(*(np.atleast_1d(a) for a in angles + [stops]))
        split = None if self.is_light_set else self._sources.split(
            env, list(zip(*(a.tolist() for a in angles))), stops.tolist(), sun, dtype)
        if split is None:
            return self.lighting(env, yaw, pitch, roll, exposure, dtype), None
        values, light = split
        return (values[0], None if light is None else light[0]) if one else split

    def _compiled_lighting(self, env):
        """On the CPU, with lighting='auto', where the compiled part loaded: the
        map's compiled Environment (a cube-lattice file's lighting only)."""
        if self.lighting_backend != "auto" or self.device.type != "cpu" or self.is_light_set:
            return None
        return env.compiled()

    def sh9(self, lightings):
        """The first nine real SH coefficients of each lighting's radiance
        [B, 9, 3] (or [9, 3] for one [l, 3]), as the batch manifest's `sh9`."""
        one = torch.as_tensor(lightings).dim() == 2
        values = self._lightings(lightings, torch.float64)
        out = torch.einsum("jb,kjc->kbc", self.domain.sh9_means(), values)
        return out[0] if one else out

    def view(self, env, yaw=0.0, pitch=0.0, roll=0.0, exposure=0.0, layout="chw"):
        """The map as the camera sees it behind the subject, times 2^exposure:
        [3, H, W] (or [H, W, 3]) float32, each pixel the rotated map's radiance
        along its centre's ray; relight(background=...) composes over it.
        Given sequences of angles (or exposures): [B, 3, H, W]."""
        if self.camera is None:
            raise ValueError(f"background env: {self.path} is a captured light set: no camera "
                             "sees the environment behind it (use black or alpha)")
        rotations = rotation_matrix(yaw, pitch, roll, self.device)
        stops = np.asarray(torch.as_tensor(exposure).cpu(), dtype=np.float64)
        one = rotations.dim() == 2 and stops.ndim == 0
        rotations = rotations.reshape(-1, 3, 3)
        # R^T d for each rotation and pixel: [B, H W, 3].
        radiance = self.environment(env).radiance(self._camera_rays() @ rotations)
        scale = torch.as_tensor(2.0 ** stops, dtype=torch.float64, device=self.device)
        image = (radiance * scale.reshape(-1, 1, 1)).to(torch.float32)
        image = image.reshape(-1, self.height, self.width, 3)
        if layout == "chw":
            image = image.permute(0, 3, 1, 2)
        return (image[0] if one else image).contiguous()

    def frame_fields(self, env, yaw=0.0, pitch=0.0, roll=0.0, exposure=0.0):
        """What the CLI's frame of this view says of itself, as a dict
        (adaptive_cpca.torch.frame_fields)."""
        return frame_fields(self, env, yaw, pitch, roll, exposure)

    def _camera_rays(self):
        """Each pixel centre's camera ray (transport/camera.h), float64 [H W, 3]."""
        if self._rays is None:
            self._rays = self._tensor(pixel_rays(self.camera, self.width, self.height))
        return self._rays

    # -- labels -------------------------------------------------------------
    LABELS = ("albedo", "normal", "tangent", "depth", "position", "mask", "object")

    def labels(self, aovs="all"):
        """The view's per-pixel labels by name, numpy arrays H x W (x C) as
        `Relighter.labels()` gives them (docs/datasets.md, "The labels"):
        albedo premultiplied by coverage, normal, tangent, planar depth, position,
        mask (coverage), object (int32, -1 for background); aovs 'all', or a
        comma-separated list of those names."""
        names = self.LABELS if aovs == "all" else tuple(aovs.split(","))
        for name in names:
            if name not in self.LABELS:
                raise ValueError(f"label {name!r}: one of {', '.join(self.LABELS)} (the "
                                 "shading is a frame's: relit / albedo)")
            if self.is_light_set and name != "mask":
                raise ValueError(f"{self.path}: cannot give the '{name}' label: a captured "
                                 "light set holds images, not the geometry or albedo under them")
        need = {"albedo": "albedo", "normal": "normal", "depth": "position",
                "position": "position", "object": "object", "mask": "coverage",
                "tangent": "lamp_sample_tangent"}  # each row's first traced sample's
        with h5py.File(self.path, "r") as f:
            keys = {need[n] for n in names} | {"coverage", "pixels", "lamp_sample_start"}
            rows = {key: f[key][:] for key in keys if key in f}
        out = {}
        for name in names:
            if need[name] not in rows:
                raise ValueError(f"{self.path}: cannot give the '{name}' label: the file has no "
                                 f"{need[name]} dataset (compress or build it again)")
            values = self._label_rows(name, rows)
            image = np.full((self.height * self.width,) + values.shape[1:],
                            -1 if name == "object" else 0, values.dtype)
            image[rows["pixels"]] = values
            out[name] = image.reshape((self.height, self.width) + values.shape[1:])
        return out

    def _label_rows(self, name, rows):
        """One label's values per row, in the file's row order."""
        if name == "albedo":  # premultiplied by coverage, as the frame is
            return (rows["coverage"][:, None] * rows["albedo"]).astype(np.float32)
        if name == "depth":  # planar: along the view axis
            eye, target = self.camera["eye"], self.camera["target"]
            forward = (target - eye) / np.linalg.norm(target - eye)
            return ((rows["position"].astype(np.float64) - eye) @ forward).astype(np.float32)
        if name == "object":
            return rows["object"].astype(np.int32)
        if name == "tangent":
            return rows["lamp_sample_tangent"][rows["lamp_sample_start"][:-1]]
        return rows[{"normal": "normal", "position": "position", "mask": "coverage"}[name]]

    # -- relighting ---------------------------------------------------------
    def _projected(self, lightings):
        """V_g^T L for each lighting: [B, N, 3] (RGB rows: channel c's block)."""
        l = self.lattice_size
        if self.channels == 1:
            return torch.einsum("wn,bwc->bnc", self.global_basis, lightings)
        return torch.stack([lightings[:, :, c] @ self.global_basis[c * l:(c + 1) * l]
                            for c in range(3)], dim=2)

    def _cluster_rows(self, lightings):
        """Each row's relit RGB, albedo applied, rows in cluster order: [B, 3, P]."""
        lightings = self._lightings(lightings)
        batch, n = lightings.shape[0], self.global_bases
        flat = self._projected(lightings).permute(1, 0, 2).reshape(n, batch * 3)  # [N, 3B]
        return self.model.relit(flat).view(batch, 3, self.rows).mul_(self._albedo_channels)

    def relit_rows(self, lightings):
        """Each row's relit RGB (albedo applied), [B, P, 3], rows in the file's
        order, before composition."""
        return self._cluster_rows(lightings)[:, :, self.file_order].permute(0, 2, 1)

    def _lightings(self, lightings, dtype=torch.float32):
        lightings = torch.as_tensor(lightings)
        if lightings.dtype not in (torch.float32, torch.float64):
            raise ValueError(f"lightings of dtype {lightings.dtype}: float32 or float64")
        lightings = lightings.to(device=self.device, dtype=dtype)
        if lightings.dim() == 2:
            lightings = lightings.unsqueeze(0)
        if lightings.dim() != 3 or lightings.shape[1:] != (self.lattice_size, 3):
            raise ValueError(f"lightings of shape {tuple(lightings.shape)}: this model takes "
                             f"[B, {self.lattice_size}, 3] (or [{self.lattice_size}, 3])")
        if not torch.isfinite(lightings).all():
            raise ValueError("lightings hold values that are not finite")
        return lightings

    def relight(self, lightings, background="black", keep_negative=False, layout="chw",
                out=None, source_light=None):
        """Images of a batch of lattice lightings [B, l, 3] (or one, [l, 3]).

        background: 'black' (3 channels), 'alpha' (4, the fourth each pixel's
        coverage) or the radiance behind the subject, [3, H, W] or [B, 3, H,
        W] in the layout asked for (view() makes the map's). Values below zero
        (a model's reconstruction can undershoot) are clamped to 0 unless
        keep_negative, as the CLI does. layout: 'chw' gives [B, C, H, W],
        'hwc' gives [B, H, W, C]. out: a float32 tensor of that shape on the
        device to write into (a training loop's buffer: no fresh images).
        source_light: the light of the maps' sources per row ([B, P, 3] or [P,
        3]), as split_lighting gives it with the lightings of the rest.
        """
        if layout not in ("chw", "hwc"):
            raise ValueError(f"layout {layout!r}: 'chw' or 'hwc'")
        behind = None
        if torch.is_tensor(background):
            behind = self._background(background, layout)
        elif background not in ("black", "alpha"):
            raise ValueError(f"background {background!r}: 'black', 'alpha' or a tensor of "
                             "radiance (view(env) makes the map's; relight_map composes it)")
        rows = self._cluster_rows(lightings)  # [B, 3, P]
        if source_light is not None:  # file order: row i is cluster position file_order[i]
            light = torch.as_tensor(source_light).to(device=self.device, dtype=torch.float32)
            light = light.reshape(-1, self.rows, 3).expand(rows.shape[0], -1, -1)
            rows.index_add_(2, self.file_order, light.permute(0, 2, 1).contiguous())
        rows.mul_(self.coverage)
        batch, channels = rows.shape[0], 4 if background == "alpha" else 3
        image = self._image(out, batch, channels, layout)
        colour = image[:, :3]
        if behind is not None:
            if behind.shape[0] not in (1, batch):
                raise ValueError(f"a background of {behind.shape[0]} images for {batch} lightings")
            colour.copy_(behind * (1 - self._coverage_image()))
            rows += colour[:, :, self.pixels]
        else:
            colour.zero_()
        if not keep_negative:
            rows.clamp_(min=0)
        colour[:, :, self.pixels] = rows
        if background == "alpha":
            image[:, 3] = self._coverage_image()
        image = image.view(batch, channels, self.height, self.width)
        if layout == "chw":
            return image if out is None else out
        hwc = image.permute(0, 2, 3, 1)
        return out.copy_(hwc) if out is not None else hwc.contiguous()

    def _image(self, out, batch, channels, layout):
        """A channels-first image [B, C, H W]: `out` itself when it is one."""
        shape = ((batch, channels, self.height, self.width) if layout == "chw" else
                 (batch, self.height, self.width, channels))
        if out is not None:
            if tuple(out.shape) != shape or out.dtype != torch.float32 or \
                    out.device != self.device or not out.is_contiguous():
                raise ValueError(f"out: a contiguous float32 tensor {list(shape)} on "
                                 f"{self.device}, not {out.dtype} {list(out.shape)} on {out.device}")
            if layout == "chw":
                return out.view(batch, channels, -1)
        return torch.empty(batch, channels, self.height * self.width, device=self.device)

    def _coverage_image(self):
        """Each pixel's coverage, [H W] (0 where no row is)."""
        if self._coverage is None:
            self._coverage = torch.zeros(self.height * self.width, device=self.device)
            self._coverage[self.pixels] = self.coverage
        return self._coverage

    def _background(self, background, layout):
        """A background tensor as [1 or B, 3, H W]."""
        b = background.to(device=self.device, dtype=torch.float32)
        if b.dim() == 3:
            b = b.unsqueeze(0)
        if layout == "hwc" and b.dim() == 4:
            b = b.permute(0, 3, 1, 2)
        if b.dim() != 4 or tuple(b.shape[1:]) != (3, self.height, self.width):
            shape = (3, self.height, self.width) if layout == "chw" else (self.height,
                                                                          self.width, 3)
            raise ValueError(f"a background of shape {tuple(background.shape)}: this model "
                             f"takes {list(shape)} or [B, {', '.join(map(str, shape))}]")
        return b.reshape(b.shape[0], 3, -1)

    def relight_map(self, env, yaw=0.0, pitch=0.0, roll=0.0, exposure=0.0, background="env",
                    keep_negative=False, layout="chw", sun="auto"):
        """One frame of a map, as `relight --env ENV --rotate ... --exposure
        --sun` writes it: [C, H, W] (or [H, W, C]) over the map ('env'),
        'black' or 'alpha'; its sun lit exactly where the compiled part
        loads (split_lighting)."""
        env = self.environment(env)
        lighting, light = self.split_lighting(env, yaw, pitch, roll, exposure, sun)
        if background == "env":
            background = self.view(env, yaw, pitch, roll, exposure, layout)
        return self.relight(lighting, background, keep_negative, layout, source_light=light)[0]

