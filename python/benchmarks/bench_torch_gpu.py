"""The GPU figures of relighting in PyTorch, as one prepared script.

  python3 bench_torch_gpu.py [--model M.h5 | --layout L.json] [--small-layout S.json] \
      [--device cuda] [--json OUT.json]

Needs only torch, h5py and numpy beside the package's pure-Python files
(PYTHONPATH=python, no compiled part). Models: a model file, or a layout
from `model_layout.py export` (default: layouts/plant1024-binary-i8.json, the
1024x1024 plant, adaptive-binary i8/f16) written with seeded values. In
the same run:

- the device's streaming read (a 4 GiB float32 sum, median of ten);
- the model relit in batches of 32 and one frame at a time, lightings on the
  device, into a buffer: ms a frame, and the model's bytes over the time of
  a pass as a share of the streaming read (targets: <= 0.2 ms a frame in
  batches of 32, <= 0.5 ms for one frame);
- a seeded 2048x1024 lat-long map integrated onto the lattice and rotated
  (target <= 0.1 ms a lighting, in passes of 32 and of one);
- RelightDataset over the 256x256 layout (default layouts/plant256-quad.json)
  feeding a training step of train_sh9's network (target >= 10,000 frames
  a second).

Prints each figure beside its target and writes them all to --json.
"""

import argparse
import json
import os
import sys
import tempfile

import torch

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "examples"))

import model_layout  # noqa: E402
from adaptive_cpca.torch import RelightDataset, TorchRelighter  # noqa: E402
from bench_torch import timed as timed_ms  # noqa: E402


def streaming_read(device, gib):
    x = torch.ones(int(gib * 2**30) // 4, device=device)
    ms = timed_ms(lambda: x.sum(), device, 10)
    return x.numel() * 4 / ms / 1e6  # GB/s


def model_file(path, layout, folder):
    if path:
        return path
    out = os.path.join(folder, "model.h5")
    with open(layout) as f:
        model_layout.write_model(json.load(f), out)
    return out


def seeded_map(device):
    """A 2048x1024 lat-long map: a gradient sky, noise, and a small sun."""
    g = torch.Generator().manual_seed(5)
    m = torch.rand(1024, 2048, 3, generator=g) * 0.2
    m += torch.linspace(1, 0.1, 1024)[:, None, None]
    m[300:306, 700:706] = 4000.0
    return m.to(device)


def relight_figures(t, device, stream, figures):
    model_bytes = t.model_bytes
    for batch, target in ((32, 0.2), (1, 0.5)):
        lightings = t.lighting("sky", [360.0 * k / batch for k in range(batch)])
        buffer = t.relight(lightings)
        ms = timed_ms(lambda: t.relight(lightings, out=buffer), device, 20) / batch
        share = model_bytes / (ms * batch) / 1e6 / stream
        figures[f"relight_ms_per_frame_batch_{batch}"] = ms
        figures[f"read_share_batch_{batch}"] = share
        print(f"  batch {batch:2d}: {ms:.4f} ms a frame (target <= {target}), "
              f"{model_bytes / 2**20:.0f} MiB a pass at {share:.0%} of the streaming read")


def lighting_figures(t, device, figures):
    env = t.environment(seeded_map(device))
    for batch in (1, 32):
        yaws = [7.0 + 360.0 * k / batch for k in range(batch)]
        ms = timed_ms(lambda: t.lighting(env, yaws, 10.0), device, 20) / batch
        figures[f"lighting_2048x1024_ms_batch_{batch}"] = ms
        print(f"  2048x1024 map integrated and rotated, {batch:2d} at once: {ms:.4f} ms a "
              "lighting (target <= 0.1)")


def training_figures(path, device, figures, steps=30, batch=256):
    import train_sh9
    data = RelightDataset(path, [seeded_map(device), "sky"], batch_size=batch, seed=1,
                          rotation="sphere", device=device, labels=None, sun="off")
    frames = iter(data)
    first = next(frames)
    net = train_sh9.network(*first["images"].shape[2:]).to(device)
    optimiser = torch.optim.Adam(net.parameters(), lr=1e-3)

    def step():
        b = next(frames)
        loss = torch.nn.functional.mse_loss(net(b["images"]), b["sh9"].reshape(batch, 27))
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()

    ms = timed_ms(step, device, steps)
    figures["training_frames_per_s_256"] = 1000 * batch / ms
    print(f"  RelightDataset feeding a training step, batches of {batch}: "
          f"{1000 * batch / ms:,.0f} frames/s (target >= 10,000)")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--model")
    p.add_argument("--layout", default=os.path.join(HERE, "layouts", "plant1024-binary-i8.json"))
    p.add_argument("--small-model")
    p.add_argument("--small-layout", default=os.path.join(HERE, "layouts", "plant256-quad.json"))
    p.add_argument("--device", default="cuda" if torch.cuda.is_available() else "cpu")
    p.add_argument("--stream-gib", type=float, default=4.0)
    p.add_argument("--json")
    a = p.parse_args()
    device = torch.device(a.device)
    name = torch.cuda.get_device_name(device) if device.type == "cuda" else "cpu"
    figures = {"device": name, "torch": torch.__version__}
    stream = streaming_read(device, a.stream_gib)
    figures["streaming_read_gb_per_s"] = stream
    print(f"{name}, torch {torch.__version__}: streaming read {stream:.0f} GB/s")
    with tempfile.TemporaryDirectory() as folder:
        path = model_file(a.model, a.layout, folder)
        t = TorchRelighter(path, device)
        figures["model"] = {"file": a.model or os.path.basename(a.layout), "width": t.width,
                            "height": t.height, "clusters": t.clusters, "kernel": t.model.kernel}
        print(f"model {figures['model']['file']}: {t.width}x{t.height}, {t.clusters} clusters, "
              f"{t.coefficient_precision}/{t.basis_precision}, kernel {t.model.kernel}")
        relight_figures(t, device, stream, figures)
        lighting_figures(t, device, figures)
        del t
        small = os.path.join(folder, "small")
        os.mkdir(small)
        training_figures(model_file(a.small_model, a.small_layout, small), device, figures)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(figures, f, indent=1)


if __name__ == "__main__":
    main()
