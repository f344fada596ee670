"""A small network learns a frame's lighting (its sh9) from relit images made
inside the training loop: `RelightDataset` over a model file replaces a
stored dataset (docs/datasets.md, "Relighting in PyTorch").

  PYTHONPATH=build/python /usr/bin/python3 python/examples/train_sh9.py MODEL \
      [--env sky --env DIR_OR_MAP ...] [--steps 150] [--batch 16] [--workers 2] [--device cpu]

Each step draws a batch of lightings (maps turned about the vertical, as
`--sample-rotation yaw`: a light from below or behind the subject shows
too little of itself in the picture to be learnt), relights it and takes
one Adam step on the mean squared error of the nine RGB coefficients,
standardised by the first batch's mean and spread. Prints the loss every few steps, and fails (exit 1) unless the mean loss of
the last fifth of the steps is below half that of the first fifth.
"""

import argparse
import sys

import torch

from adaptive_cpca.torch import RelightDataset


def network(height, width):
    """Images [B, 3, H, W] to sh9 [B, 27]: where the subject is lit tells
    where the light comes from, so the head keeps the layout (no pooling)."""
    size = (-(-height // 8)) * (-(-width // 8))
    return torch.nn.Sequential(
        torch.nn.Conv2d(3, 16, 3, stride=2, padding=1), torch.nn.ReLU(),
        torch.nn.Conv2d(16, 32, 3, stride=2, padding=1), torch.nn.ReLU(),
        torch.nn.Conv2d(32, 8, 3, stride=2, padding=1), torch.nn.ReLU(),
        torch.nn.Flatten(), torch.nn.Linear(8 * size, 27))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("models", nargs="+")
    p.add_argument("--env", action="append", default=None, help="maps to draw from")
    p.add_argument("--steps", type=int, default=150)
    p.add_argument("--batch", type=int, default=16)
    p.add_argument("--workers", type=int, default=0)
    p.add_argument("--device", default="cpu")
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    maps = a.env or ["sky", "sun:40,30,8,300", "sun:80,200,20,40"]
    torch.manual_seed(a.seed)
    workers = 0 if torch.device(a.device).type == "cuda" else a.workers
    # Suns lit exactly need the compiled part, in the main process alone.
    dataset = RelightDataset(a.models, maps, batch_size=a.batch, seed=a.seed,
                             draws=a.steps * a.batch, rotation="yaw", device=a.device,
                             labels=None, sun="auto" if workers == 0 else "off")
    loader = torch.utils.data.DataLoader(dataset, batch_size=None, num_workers=workers)
    model, optimiser = None, None
    brightness, mean, scale, losses = None, None, None, []
    for step, batch in enumerate(loader):
        images = batch["images"].to(a.device).float()
        target = batch["sh9"].to(a.device).reshape(len(images), 27)
        if model is None:  # inputs and targets of order 1, by the first batch
            model = network(*images.shape[2:]).to(a.device)
            optimiser = torch.optim.Adam(model.parameters(), lr=5e-3)
            brightness = images.mean().clamp(min=1e-6)
            mean, scale = target.mean(dim=0), target.std(dim=0).clamp(min=1e-6)
        images = images / brightness
        loss = torch.nn.functional.mse_loss(model(images), (target - mean) / scale)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        losses.append(float(loss))
        if step % 10 == 0 or step == a.steps - 1:
            print(f"step {step:4d}: loss {losses[-1]:.4f}")
    fifth = max(1, len(losses) // 5)
    first, last = sum(losses[:fifth]) / fifth, sum(losses[-fifth:]) / fifth
    print(f"mean loss, first fifth {first:.4f}, last fifth {last:.4f}")
    if not last < 0.5 * first:
        print("the loss did not fall to half", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
