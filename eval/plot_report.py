#!/usr/bin/python3
"""Plots for adaptive-cpca's reports (eval, bench scaling, analyze).

Called by the CLI as: plot_report.py KIND REPORT_DIR. It reads the CSV files
the command wrote there and writes PNGs beside them. Needs matplotlib
(Debian: python3-matplotlib, for /usr/bin/python3).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def pareto(points):
    """Points not beaten on both axes (lower is better on both)."""
    front, best = [], math.inf
    for x, y in sorted(points):
        if y < best:
            front.append((x, y))
            best = y
    return front


def finish(fig, ax, path, xlabel, ylabel, title, legend_size=8):
    """Labels, grid and legend, then writes the figure and closes it."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=legend_size)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_eval(folder):
    rows = read_rows(os.path.join(folder, "settings.csv"))
    methods = sorted({r["method"] for r in rows})
    for x_key, name, label in (
        ("ms_per_frame", "error_vs_ms.png", "ms per frame (median)"),
        ("cost_per_pixel", "error_vs_cost.png", "multiply-adds per pixel (eq. 18)"),
    ):
        fig, ax = plt.subplots(figsize=(8, 5.5))
        everything = []
        for i, m in enumerate(methods):
            if m == "dense":
                # Exact up to rounding: a vertical line, not a point decades below the rest.
                xs = [number(r[x_key]) for r in rows if r["method"] == m]
                if xs and xs[0] > 0:
                    ax.axvline(xs[0], color=f"C{i}", linestyle="--", label="dense (ground truth)")
                continue
            pts = sorted(
                (number(r[x_key]), number(r["image_error"]))
                for r in rows
                if r["method"] == m
            )
            pts = [(x, y) for x, y in pts if x > 0 and y > 0 and math.isfinite(x) and math.isfinite(y)]
            if not pts:
                continue
            everything += pts
            front = pareto(pts)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o", alpha=0.35, color=f"C{i}")
            ax.plot([p[0] for p in front], [p[1] for p in front], "-o", color=f"C{i}", label=m)
        front = pareto(everything)
        if front:
            ax.step([p[0] for p in front], [p[1] for p in front], "k--", where="post",
                    linewidth=1, label="Pareto front (all)")
        for target in (0.01, 0.03):
            ax.axhline(target, color="grey", linewidth=0.6, linestyle=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        finish(fig, ax, os.path.join(folder, name), label, "relative L2 error (RMS over maps)",
               "error against " + ("run time" if x_key == "ms_per_frame" else "cost"))


def plot_scaling(folder):
    rows = read_rows(os.path.join(folder, "scaling.csv"))
    px = [number(r["pixels"]) for r in rows]
    total = [number(r["total_cost"]) for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    ax = axes[0]
    ax.loglog(px, total, "-o", label="measured total cost")
    predicted = [total[0]]
    for r in rows[1:]:
        predicted.append(predicted[-1] * number(r["predicted_ratio"]))
    ax.loglog(px, predicted, "--s", label="4 mu^2 per 4x pixels (from the coarser size)")
    ax.loglog(px, [total[0] * p / px[0] for p in px], ":", color="grey", label="linear in pixels")
    ax.set_xlabel("image pixels")
    ax.set_ylabel("total cost (multiply-adds per frame)")
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.semilogx(px, [number(r["cost_per_pixel"]) for r in rows], "-o", label="cost per pixel")
    ax2 = ax.twinx()
    ax2.semilogx(px, [number(r["ms_per_frame"]) for r in rows], "-s", color="C3", label="ms per frame")
    ax.set_xlabel("image pixels")
    ax.set_ylabel("cost per pixel")
    ax2.set_ylabel("ms per frame", color="C3")
    ax.grid(True, which="both", alpha=0.25)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "scaling.png"), dpi=110)
    plt.close(fig)


def plot_analyze(folder):
    rows = read_rows(os.path.join(folder, "dimensionality.csv"))
    slopes = {r["centre"]: r for r in read_rows(os.path.join(folder, "slopes.csv"))}
    fig, ax = plt.subplots(figsize=(7, 5))
    for i, centre in enumerate(sorted({r["centre"] for r in rows}, key=lambda c: int(c))):
        pts = [(number(r["area"]), number(r["dimensionality"])) for r in rows if r["centre"] == centre]
        pts = [(a, n) for a, n in pts if a > 0 and n > 0]
        if not pts:
            continue
        s = slopes.get(centre, {})
        label = f"centre {s.get('x', '?')},{s.get('y', '?')}: slope {number(s.get('slope')):.2f}"
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], "-o", color=f"C{i % 10}", label=label, markersize=3)
    finish(fig, ax, os.path.join(folder, "dimensionality.png"), "patch area (pixels)",
           "eigenvalues for 99.95% of the energy", "dimensionality against patch area", 7)

    blocks = read_rows(os.path.join(folder, "block_cost.csv"))
    fig, ax = plt.subplots(figsize=(7, 5))
    p = [number(r["block_pixels"]) for r in blocks]
    ax.loglog(p, [number(r["cost_per_pixel"]) for r in blocks], "-o", color="k", label="total")
    ax.loglog(p, [number(r["global_to_local"]) for r in blocks], "-o", color="C0",
              label="global to local bases (n N per cluster)")
    ax.loglog(p, [number(r["local_to_pixel"]) for r in blocks], "-o", color="C3",
              label="local bases to pixels (n p per cluster)")
    n_global = number(blocks[0]["global_bases"]) if blocks else math.nan
    if math.isfinite(n_global):
        ax.axvline(n_global, color="grey", linestyle=":", label=f"p = N = {int(n_global)}")
    finish(fig, ax, os.path.join(folder, "block_cost.png"), "block size (pixels per block)",
           "cost per pixel", "cost against patch size (fixed blocks)")


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("eval", "scaling", "analyze"):
        sys.exit("usage: plot_report.py eval|scaling|analyze REPORT_DIR")
    {"eval": plot_eval, "scaling": plot_scaling, "analyze": plot_analyze}[sys.argv[1]](sys.argv[2])


if __name__ == "__main__":
    main()
