"""The table of scripts/cycles/olat.sh: relative L2 over the pixels Cycles
covers (its alpha), each image against a reference, for every light count and
HDRI, and the noise of both sides measured with a second seed.

  PYTHONPATH=build/python python3 compare_olat.py OUT_DIR "156 331" "forest city"

Writes OUT_DIR/comparison.json and prints the table.
"""

import json
import math
import sys

import numpy as np

import adaptive_cpca as ac


def image(path):
    return ac.read_image(path).astype(np.float64)


def relative_l2(test, reference, mask):
    d = test[..., :3][mask] - reference[..., :3][mask]
    return float(np.sqrt((d ** 2).sum() / (reference[..., :3][mask] ** 2).sum()))


def main():
    out, lights, hdris = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
    rows = []
    for name in hdris:
        full, full_2 = image(f"{out}/{name}-full.exr"), image(f"{out}/{name}-full-2.exr")
        for n in lights:
            d = f"{out}/n{n}/{name}"
            cycles, cycles_2 = image(f"{d}/cycles.exr"), image(f"{d}/cycles-2.exr")
            ours, ours_2 = image(f"{d}/ours.exr"), image(f"{d}/ours-2.exr")
            model = image(f"{d}/model.exr")
            covered = cycles[..., 3] > 0
            whole = cycles[..., 3] > 0.999  # every camera sample met the scene
            noise_lamps = relative_l2(cycles_2, cycles, covered)
            noise_set = relative_l2(ours_2, ours, covered)
            row = {
                "hdri": name, "lights": int(n), "covered_pixels": int(covered.sum()),
                "imported_vs_cycles_lamps": relative_l2(ours, cycles, covered),
                "imported_vs_cycles_lamps_whole_pixels": relative_l2(ours, cycles, whole),
                "energy_ratio": float(ours[..., :3][covered].sum()
                                      / cycles[..., :3][covered].sum()),
                "model_vs_cycles_lamps": relative_l2(model, cycles, covered),
                # Two renders of one seed each differ by sqrt(2) times either's noise.
                "cycles_lamps_seed_1_vs_2": noise_lamps,
                "olat_set_seed_1_vs_2": noise_set,
                "noise_alone_would_give": math.sqrt((noise_lamps ** 2 + noise_set ** 2) / 2),
                "cycles_lamps_vs_cycles_map": relative_l2(cycles, full, covered),
                "imported_vs_cycles_map": relative_l2(ours, full, covered),
                "cycles_map_seed_1_vs_2": relative_l2(full_2, full, covered),
            }
            rows.append(row)
    json.dump(rows, open(f"{out}/comparison.json", "w"), indent=2)

    def pct(v):
        return f"{100 * v:.2f}%"

    print("| HDRI | N | imported vs Cycles, N lamps (whole pixels) | noise alone | model | "
          "Cycles lamps vs map | imported vs map | map noise |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['hdri']} | {r['lights']} | {pct(r['imported_vs_cycles_lamps'])} "
              f"({pct(r['imported_vs_cycles_lamps_whole_pixels'])}) | "
              f"{pct(r['noise_alone_would_give'])} | {pct(r['model_vs_cycles_lamps'])} | "
              f"{pct(r['cycles_lamps_vs_cycles_map'])} | {pct(r['imported_vs_cycles_map'])} | "
              f"{pct(r['cycles_map_seed_1_vs_2'] / math.sqrt(2))} |")


main()
