"""A small relit dataset: one model under random Debian world HDRIs at random
yaws, saved as .npy images (H x W x 3 float32, linear) with a manifest.csv.
numpy and the module only.

  PYTHONPATH=build/python /usr/bin/python3 python/examples/make_dataset.py \
      plant-model.h5 dataset/ --count 64 --seed 1
"""

import argparse
import csv
import glob
import os

import numpy as np

import adaptive_cpca as ac


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("model", help="model (or transport) file")
    p.add_argument("out", help="directory to write")
    p.add_argument("--count", type=int, default=32)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--worlds", default="/usr/share/blender/datafiles/studiolights/world",
                   help="folder of lat-long .exr maps (Debian's blender-data)")
    a = p.parse_args()

    worlds = sorted(glob.glob(os.path.join(a.worlds, "*.exr")))
    if not worlds:
        raise SystemExit(f"no .exr maps in {a.worlds} (apt-get install blender-data)")
    rng = np.random.default_rng(a.seed)
    relighter = ac.Relighter(a.model)
    envs = {}  # each map is read and checked once
    image = np.empty((relighter.height, relighter.width, 3), np.float32)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "manifest.csv"), "w", newline="") as f:
        manifest = csv.writer(f)
        manifest.writerow(["file", "env", "yaw"])
        for i in range(a.count):
            world = worlds[rng.integers(len(worlds))]
            yaw = float(rng.uniform(0, 360))
            if world not in envs:
                envs[world] = ac.Environment(world)
            relighter.relight(envs[world], yaw=yaw, background="env", out=image)
            name = f"{i:05d}.npy"
            np.save(os.path.join(a.out, name), image)
            manifest.writerow([name, os.path.basename(world), repr(yaw)])
    print(f"wrote {a.count} images of {relighter.width}x{relighter.height} to {a.out}")


if __name__ == "__main__":
    main()
