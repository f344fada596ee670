#!/usr/bin/python3
"""The Monte Carlo noise of a transport with interreflections.

Relights a transport and a reference made with more paths per sample (16x is
the rule in docs/results.md) under the same lightings, and prints, per
lighting, the RMS difference over covered pixels relative to the mean covered
pixel, and how much the bounced light adds (the reference against the direct
transport, when one is given).

    python3 indirect_noise.py TRANSPORT REFERENCE [--direct DIRECT] [--env SPEC ...]
"""
import argparse
import json
import sys

import numpy as np

import adaptive_cpca as ac

DEFAULT_ENVS = ["sky", "sun:50,30,4,1000", "constant:1"]


def relit(path, env):
    image = ac.open(path).relight(ac.Environment(env), background="alpha")
    return image[..., :3].astype(np.float64), image[..., 3] > 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("transport")
    parser.add_argument("reference")
    parser.add_argument("--direct", help="the same scene without bounces")
    parser.add_argument("--env", action="append", help="lighting spec (repeatable)")
    parser.add_argument("--json", help="write the figures here")
    args = parser.parse_args()
    rows = []
    for env in args.env or DEFAULT_ENVS:
        image, covered = relit(args.transport, env)
        reference, _ = relit(args.reference, env)
        mean = reference[covered].mean()
        noise = np.sqrt(((image - reference)[covered] ** 2).mean()) / mean
        row = {"env": env, "mean_pixel": mean, "noise": noise}
        if args.direct:
            direct, _ = relit(args.direct, env)
            row["indirect_share"] = 1 - direct[covered].mean() / mean
        rows.append(row)
        print(f"{env:24s} noise {100 * noise:6.3f}% of the mean pixel"
              + (f", bounced light {100 * row['indirect_share']:5.2f}% of it"
                 if args.direct else ""))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
