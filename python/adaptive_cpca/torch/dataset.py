"""Relit frames made inside the training loop: a seeded torch dataset.

`RelightDataset` draws lightings as the CLI's `--env-sample` does (the same
SplitMix64 draws for the same seed: adaptive_cpca.sampling) and relights them
from model files with `TorchRelighter`, so that a model file replaces a
stored dataset (docs/datasets.md, "Relighting in PyTorch").

Batch k holds draws kB .. kB + B - 1 and is relit from view k mod V (V the
models given); under a DataLoader with W workers it is made by worker k mod
W, so the stream of batches is the same for any W.
"""

import math
import os

import torch

from .._contract import BACKGROUNDS, MAP_FILE_EXTENSIONS, MAX_EXPOSURE_JITTER
from ..io import read_image
from ..sampling import draw, epoch_seed
from .lighting import Environment
from .relighter import TorchRelighter
from .sources import check_sun

__all__ = ["RelightDataset"]


def _expanded(maps):
    """Each directory replaced by its maps, as the CLI's --env expands it."""
    out = []
    for spec in maps:
        if isinstance(spec, str) and os.path.isdir(spec):
            found = sorted(os.path.join(spec, name) for name in os.listdir(spec)
                           if os.path.splitext(name)[1].lower() in MAP_FILE_EXTENSIONS)
            if not found:
                raise ValueError(f"environment {spec!r}: the directory holds no .exr/.hdr maps")
            out += found
        else:
            out.append(spec)
    return out


class RelightDataset(torch.utils.data.IterableDataset):
    """Batches of B relit frames and their labels, drawn from a seed.

    models: one model file or several (views of one subject, or subjects);
    maps: `--env` specs, map files or map tensors to draw from. Each item is
    a dict: `images` [B, C, H, W] (`layout="hwc"`: [B, H, W, C]) of `dtype`
    (float32 or float16), `sh9` [B, 9, 3] float32 (of the rotated map,
    before exposure, as the batch manifest's), `draw` [B] (each frame's draw
    index), `map`, `yaw`, `pitch`, `roll`, `exposure` [B] (the draws, the
    batch's `exposure` plus each draw's offset), `view` (the model's index),
    `labels` (the view's `TorchRelighter.labels()` as tensors, channels
    first under `layout="chw"`) and `camera` (eye, target, up, fov_deg, and
    transforms.json's transform_matrix, fl_x, fl_y, cx, cy, w, h; none
    for a captured light set).

    draws: N draws in all (the last batch may be short), or None for an
    endless stream; set_epoch(e) draws from another seed each epoch (epoch
    0: `seed` itself, as the CLI's --seed). rotation: 'yaw' or 'sphere',
    exposure_jitter in stops, as --sample-rotation and --exposure-jitter;
    a directory among the maps stands for the maps it holds (.exr, .hdr,
    .pfm, .tif, sorted), as for --env. device: where the models are held and frames made
    (CUDA only with num_workers=0: CUDA does not run in forked workers).
    sun: 'auto', 'off' or K, as `relight --sun`: each map's sun and bright
    lamps lit exactly by the compiled part on the CPU, the frame composed on
    the device (adaptive_cpca.torch.sources); 'auto' needs num_workers=0, as
    the compiled part does not run in forked workers, and 'off' lights the
    whole map through the lattice under any worker count. `sh9` is the whole
    map's either way.
    """

    def __init__(self, models, maps, batch_size=8, seed=0, draws=None, rotation="yaw",
                 exposure=0.0, exposure_jitter=0.0, background="black", keep_negative=False,
                 layout="chw", dtype=torch.float32, device="cpu", labels="all", sun="auto"):
        super().__init__()
        self.models = [models] if isinstance(models, str) else list(models)
        self.maps = _expanded([maps] if isinstance(maps, str) or torch.is_tensor(maps) else maps)
        # Map files read now, before any DataLoader forks: the readers' thread
        # pools do not survive a fork.
        self._pixels = {k: read_image(m) for k, m in enumerate(self.maps)
                        if isinstance(m, str) and os.path.isfile(m)}
        if not self.models or not self.maps:
            raise ValueError("RelightDataset needs at least one model and one map")
        if batch_size < 1 or (draws is not None and draws < 1):
            raise ValueError(f"batch_size {batch_size} and draws {draws}: at least 1 each")
        if background not in BACKGROUNDS:
            raise ValueError(f"background {background!r}: one of {', '.join(BACKGROUNDS)}")
        if dtype not in (torch.float32, torch.float16):
            raise ValueError(f"dtype {dtype}: torch.float32 or torch.float16")
        if not (math.isfinite(exposure) and 0 <= exposure_jitter <= MAX_EXPOSURE_JITTER):
            raise ValueError(f"exposure {exposure} and jitter {exposure_jitter}: finite, "
                             f"jitter in 0..{MAX_EXPOSURE_JITTER:g} stops")
        draw(0, len(self.maps), seed, rotation)  # refuses an unknown rotation now
        self.sun = check_sun(sun)
        self.batch_size, self.seed, self.draws = batch_size, seed, draws
        self.rotation, self.exposure, self.exposure_jitter = rotation, exposure, exposure_jitter
        self.background, self.keep_negative, self.layout = background, keep_negative, layout
        self.dtype, self.device, self.label_names = dtype, torch.device(device), labels
        self.epoch = 0
        self._views = None

    def set_epoch(self, epoch):
        """Draw from epoch e's seed (sampling.epoch_seed) from the next iteration on."""
        self.epoch = int(epoch)

    def __len__(self):
        if self.draws is None:
            raise TypeError("an endless RelightDataset (draws=None) has no length")
        return -(-self.draws // self.batch_size)

    def _open(self):
        """Each view's relighter, maps and labels, made where the batches are."""
        if self._views is None:
            views = []
            for path in self.models:
                r = TorchRelighter(path, self.device)
                labels = {}
                if self.label_names:
                    names = "mask" if r.is_light_set else self.label_names
                    for name, value in r.labels(names).items():
                        t = torch.from_numpy(value).to(self.device)
                        if self.layout == "chw":
                            t = t.permute(2, 0, 1) if t.dim() == 3 else t.unsqueeze(0)
                        labels[name] = t.contiguous()
                camera = None if r.camera is None else {
                    k: torch.as_tensor(v) for k, v in r.camera.items()}
                views.append((r, labels, camera))
            self._views = views
            self._environments = [
                Environment(m, self.device, pixels=self._pixels.get(k)) if isinstance(m, str)
                else views[0][0].environment(m) for k, m in enumerate(self.maps)]
        return self._views

    def batch(self, k):
        """Batch k of the current epoch's stream."""
        views = self._open()
        view = k % len(views)
        r, labels, camera = views[view]
        first = k * self.batch_size
        last = first + self.batch_size if self.draws is None else min(self.draws,
                                                                       first + self.batch_size)
        seed = epoch_seed(self.seed, self.epoch)
        drawn = [draw(i, len(self.maps), seed, self.rotation, self.exposure_jitter)
                 for i in range(first, last)]
        # One pass over each map for all the draws that turn it.
        count = len(drawn)
        lightings = torch.empty(count, r.lattice_size, 3, dtype=torch.float64, device=self.device)
        for m in sorted({d.map for d in drawn}):
            mine = [k for k, d in enumerate(drawn) if d.map == m]
            angles = [[drawn[k][a] for k in mine] for a in (1, 2, 3)]
            lightings[mine] = r.lighting(self._environments[m], *angles, dtype=torch.float64)
        sh9 = r.sh9(lightings)
        stops = torch.tensor([self.exposure + d.exposure for d in drawn], dtype=torch.float64,
                             device=self.device)
        lightings *= (2.0 ** stops)[:, None, None]
        light = self._source_light(r, drawn, stops, lightings)
        background = self.background
        if background == "env":
            background = torch.empty((count, 3, r.height, r.width) if self.layout == "chw" else
                                     (count, r.height, r.width, 3), device=self.device)
            for m in sorted({d.map for d in drawn}):
                mine = [k for k, d in enumerate(drawn) if d.map == m]
                angles = [[drawn[k][a] for k in mine] for a in (1, 2, 3)]
                background[mine] = r.view(self._environments[m], *angles, stops[mine],
                                          self.layout)
        images = r.relight(lightings, background, self.keep_negative, self.layout,
                           source_light=light)

        def column(index):
            return torch.tensor([d[index] for d in drawn], dtype=torch.float64)

        return {"images": images.to(self.dtype), "sh9": sh9.to(torch.float32),
                "draw": torch.arange(first, last), "map": column(0).long(),
                "yaw": column(1), "pitch": column(2), "roll": column(3),
                "exposure": self.exposure + column(4), "view": view, "labels": labels,
                "camera": camera}

    def _source_light(self, r, drawn, stops, lightings):
        """Each frame's sources lit exactly ([B, P, 3], None where none is):
        the lattice lightings of those frames replaced by the rest's."""
        if self.sun == "off":
            return None
        light = None
        for m in sorted({d.map for d in drawn}):
            mine = [k for k, d in enumerate(drawn) if d.map == m]
            angles = [[drawn[k][a] for k in mine] for a in (1, 2, 3)]
            rest, rows = r.split_lighting(self._environments[m], *angles, stops[mine].cpu(),
                                          sun=self.sun, dtype=torch.float64)
            if rows is None:
                continue
            if light is None:
                light = torch.zeros(len(drawn), r.rows, 3, device=self.device)
            lightings[mine], light[mine] = rest, rows
        return light

    def __iter__(self):
        info = torch.utils.data.get_worker_info()
        worker, workers = (0, 1) if info is None else (info.id, info.num_workers)
        if workers > 1 and self.device.type == "cuda":
            raise RuntimeError("RelightDataset on CUDA runs in the main process "
                               "(DataLoader num_workers=0): CUDA does not run in forked workers")
        batches = None if self.draws is None else len(self)
        k = worker
        while batches is None or k < batches:
            yield self.batch(k)
            k += workers
