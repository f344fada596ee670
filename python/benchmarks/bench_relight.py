"""Relight from Python against the CLI's timing mode, same model, same run.

  PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/bench_relight.py MODEL \
      [--frames 50] [--rounds 3] [--env sky] [--cli build/tools/adaptive-cpca]

Both time frames after a warm-up: the CLI with `relight --frames K` (its
median ms/frame: the relight of a lighting already on the lattice), Python
with relight(lighting, out=buffer) in a loop over a Lighting made once
(median of the same count; each call also composes the image into the
buffer, which the CLI's timing leaves out). The two alternate for a few
rounds, since a shared machine's memory bandwidth drifts within seconds;
prints each round and the median of the rounds' ratios.
"""

import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np

import adaptive_cpca as ac


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("model")
    p.add_argument("--frames", type=int, default=50)
    p.add_argument("--env", default="sky")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--cli", default="build/tools/adaptive-cpca")
    a = p.parse_args()

    r = ac.Relighter(a.model)
    env = ac.Environment(a.env)
    out = np.empty((r.height, r.width, 3), np.float32)
    light = r.lighting(env)  # integrated once, as the CLI does before timing

    def cli_ms():
        with tempfile.TemporaryDirectory() as tmp:
            report = os.path.join(tmp, "t.json")
            subprocess.run([a.cli, "relight", a.model, "--env", a.env, "--frames",
                            str(a.frames), "--background", "black", "--out",
                            os.path.join(tmp, "x.exr"), "--quiet", "--json", report], check=True)
            with open(report) as f:
                return json.load(f)["ms_per_frame_median"]

    def python_ms():
        r.relight(light, background="black", out=out)  # warm-up
        ms = []
        for _ in range(a.frames):
            start = time.perf_counter()
            r.relight(light, background="black", out=out)
            ms.append(1000 * (time.perf_counter() - start))
        return statistics.median(ms)

    ratios = []
    for k in range(a.rounds):
        c, py = cli_ms(), python_ms()
        ratios.append(py / c)
        print(f"round {k + 1}: CLI {c:.3f} ms/frame, Python {py:.3f} ms/frame, "
              f"Python / CLI {py / c:.3f}")
    print(f"{r.width}x{r.height} {r.method}: Python / CLI {statistics.median(ratios):.3f} "
          f"(median of {a.rounds} rounds)")


if __name__ == "__main__":
    main()
