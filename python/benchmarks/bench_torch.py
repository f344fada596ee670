"""TorchRelighter against the compiled relighter, same model, same run.

  PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/bench_torch.py MODEL... \
      [--device cpu] [--frames 20] [--batch 1 32] [--cli build/tools/adaptive-cpca]

Per model: the CLI's `bench relight` (its median ms/frame for a lighting
already on the lattice, and the machine's streaming read in the same run),
then adaptive_cpca.torch's relight of lightings made once on the device, at
each batch size (median ms per frame over --frames frames after a warm-up;
fresh images each call, and into one buffer, `out=`, as a training loop
would reuse it),
and the lighting made on the device (sky, and the first Blender world map
rotated); with --dataset, RelightDataset (the Blender world maps and the
sky, turned over the sphere) feeding a training step of train_sh9's network
at each --workers count, against the relight alone of the same batches.
Prints each figure, its ratio to the compiled relighter and the bytes a
frame reads over the streaming read.
"""

import argparse
import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import torch

from adaptive_cpca.torch import RelightDataset, TorchRelighter

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
import train_sh9  # noqa: E402

WORLDS = "/usr/share/blender/datafiles/studiolights/world"


def compiled_figures(cli, model, frames):
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "bench.json")
        subprocess.run([cli, "bench", "relight", model, "--env", "sky", "--frames", str(frames),
                        "--quiet", "--json", report], check=True, stdout=subprocess.DEVNULL)
        with open(report) as f:
            data = json.load(f)
    fastest = min(r["ms_per_frame_median"] for r in data["relighters"] if r["file"] == model)
    return fastest, data["stream_gb_per_s"], data["relighters"][0]["bytes_per_frame"]


def timed(call, device, repeats):
    call()  # warm-up
    ms = []
    for _ in range(repeats):
        if device.type == "cuda":
            torch.cuda.synchronize(device)
        start = time.perf_counter()
        call()
        if device.type == "cuda":
            torch.cuda.synchronize(device)
        ms.append(1000 * (time.perf_counter() - start))
    return statistics.median(ms)


def dataset_figures(model, t, batch, workers, batches=8):
    """Frames a second of RelightDataset feeding a training step, per worker count."""
    maps = sorted(glob.glob(os.path.join(WORLDS, "*.exr"))) + ["sky"]
    net = train_sh9.network(t.height, t.width)
    optimiser = torch.optim.Adam(net.parameters(), lr=1e-3)
    for w in workers:
        data = RelightDataset(model, maps, batch_size=batch, seed=3, draws=batch * batches,
                              rotation="sphere", labels=None, sun="off")  # any worker count
        start = time.perf_counter()
        for b in torch.utils.data.DataLoader(data, batch_size=None, num_workers=w):
            loss = torch.nn.functional.mse_loss(net(b["images"]), b["sh9"].reshape(-1, 27))
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
        rate = batch * batches / (time.perf_counter() - start)
        print(f"  RelightDataset, batches of {batch}, {w} workers, feeding a training step: "
              f"{rate:7.1f} frames/s")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("models", nargs="+")
    p.add_argument("--device", default="cpu")
    p.add_argument("--kernel", default="auto", choices=["auto", "clusters", "sparse"])
    p.add_argument("--frames", type=int, default=20)
    p.add_argument("--batch", type=int, nargs="+", default=[1, 32])
    p.add_argument("--cli", default="build/tools/adaptive-cpca")
    p.add_argument("--dataset", action="store_true")
    p.add_argument("--workers", type=int, nargs="+", default=[0, 2])
    a = p.parse_args()
    device = torch.device(a.device)
    print(f"torch {torch.__version__}, {torch.get_num_threads()} threads, device {device}")
    for model in a.models:
        cpp_ms, stream, bytes_per_frame = compiled_figures(a.cli, model, a.frames)
        t = TorchRelighter(model, device, kernel=a.kernel)
        print(f"\n{model}: {t.method} {t.width}x{t.height}, {t.clusters} clusters, "
              f"{t.coefficient_precision}/{t.basis_precision}, kernel {t.model.kernel}, "
              f"{bytes_per_frame / 2**20:.1f} MiB a frame")
        print(f"  streaming read {stream:.1f} GB/s; compiled relighter {cpp_ms:.3f} ms/frame "
              f"({bytes_per_frame / cpp_ms / 1e6:.1f} GB/s, "
              f"{bytes_per_frame / cpp_ms / 1e6 / stream:.0%} of the stream)")
        sky = t.environment("sky")
        for batch in a.batch:
            lightings = torch.stack([t.lighting(sky, yaw=360.0 * k / batch)
                                     for k in range(batch)])
            repeats = max(3, a.frames // batch)
            buffer = t.relight(lightings)
            for what, call in (("fresh images", lambda: t.relight(lightings)),
                               ("into a buffer", lambda: t.relight(lightings, out=buffer))):
                ms = timed(call, device, repeats) / batch
                print(f"  torch batch {batch:3d}, {what:13s}: {ms:8.3f} ms/frame, "
                      f"{1000 / ms:8.1f} frames/s, {ms / cpp_ms:5.2f}x the compiled relighter's")
        if a.dataset:
            dataset_figures(model, t, a.batch[-1], a.workers)
        worlds = sorted(glob.glob(os.path.join(WORLDS, "*.exr")))
        for name, env in [("sky", sky)] + [(os.path.basename(w), t.environment(w))
                                           for w in worlds[:1]]:
            ms = timed(lambda: t.lighting(env, yaw=33.0, pitch=5.0), device, 5)
            print(f"  lighting of {name} rotated, made on {device}: {ms:.2f} ms")


if __name__ == "__main__":
    main()
