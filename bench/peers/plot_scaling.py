#!/usr/bin/python3
"""Plots invmap's scaling study (the CSV of invmap_bench_peers --scaling-csv).

Writes two PNGs next to the CSV (or into --out-dir):
  scaling_cells.png  points/s against the number of cells (log-log), and per
                     geometry the microseconds per point against ln(cells)
                     with a least-squares a + b ln(cells) fit;
  scaling_batch.png  points/s against the batch size, one line per geometry and
                     thread count.

Usage: /usr/bin/python3 plot_scaling.py peers_scaling.csv [--out-dir DIR]
Needs Debian's python3-matplotlib (and python3-numpy, which it pulls in).
"""

import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only: no display on a build machine
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    """Returns the CSV rows with numeric fields converted."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for key in ("cells", "points", "threads"):
            r[key] = int(r[key])
        for key in ("seconds", "points_per_second", "build_seconds"):
            r[key] = float(r[key])
    return rows


def series_of(rows, study):
    """Groups one study's rows by (geometry, threads), each sorted by its x value."""
    x_key = "cells" if study == "cells" else "points"
    groups = {}
    for r in rows:
        if r["study"] == study:
            groups.setdefault((r["geometry"], r["threads"]), []).append(r)
    for key in groups:
        groups[key].sort(key=lambda r: r[x_key])
    return groups


def fit_log(cells, micros):
    """Least-squares fit micros = a + b * ln(cells); returns (a, b)."""
    xs = [math.log(c) for c in cells]
    n = len(xs)
    mx, my = sum(xs) / n, sum(micros) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0:
        return my, 0.0
    b = sum((x - mx) * (y - my) for x, y in zip(xs, micros)) / sxx
    return my - b * mx, b


def plot_cells(rows, path):
    """Throughput against cells (log-log), then one panel per geometry with the
    cost per point against ln(cells), where log growth is a straight line."""
    groups = series_of(rows, "cells")
    geometries = sorted({geometry for geometry, _ in groups})
    fig, axes = plt.subplots(1, 1 + len(geometries), figsize=(5.5 * (1 + len(geometries)), 4.5))
    throughput, cost_axes = axes[0], dict(zip(geometries, axes[1:]))
    for (geometry, threads), series in sorted(groups.items()):
        cells = [r["cells"] for r in series]
        rates = [r["points_per_second"] for r in series]
        micros = [1e6 / r for r in rates]
        label = f"{geometry}, {threads} thread{'s' if threads > 1 else ''}"
        line = throughput.plot(cells, rates, marker="o", label=label)[0]
        ax = cost_axes[geometry]
        ax.plot(cells, micros, marker="o", color=line.get_color(), label=label)
        if len(cells) >= 2:
            a, b = fit_log(cells, micros)
            ax.plot(cells, [a + b * math.log(c) for c in cells], linestyle="--", color=line.get_color(), alpha=0.6,
                    label=f"fit {a:.2f} + {b:.2f} ln(cells)")
    throughput.set_xscale("log")
    throughput.set_yscale("log")
    throughput.set_ylabel("points per second")
    throughput.set_title("Throughput as the geometry grows")
    for geometry, ax in cost_axes.items():
        ax.set_xscale("log")
        ax.set_ylim(bottom=0)
        ax.set_ylabel("microseconds per point")
        ax.set_title(f"{geometry}: cost per point (log growth is a line)")
    for ax in axes:
        ax.set_xlabel("cells")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_batch(rows, path):
    groups = series_of(rows, "batch")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for (geometry, threads), series in sorted(groups.items()):
        points = [r["points"] for r in series]
        rates = [r["points_per_second"] for r in series]
        cells = series[0]["cells"]
        ax.plot(points, rates, marker="o",
                label=f"{geometry} ({cells} cells), {threads} thread{'s' if threads > 1 else ''}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("points in the batch")
    ax.set_ylabel("points per second")
    ax.set_title("Throughput as the batch grows")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", help="the scaling CSV written by invmap_bench_peers")
    parser.add_argument("--out-dir", help="where to write the PNGs (default: the CSV's directory)")
    args = parser.parse_args()
    rows = read_rows(args.csv)
    if not rows:
        sys.exit(f"{args.csv}: no rows")
    out_dir = args.out_dir or os.path.dirname(os.path.abspath(args.csv))
    os.makedirs(out_dir, exist_ok=True)
    for name, plot in (("scaling_cells.png", plot_cells), ("scaling_batch.png", plot_batch)):
        path = os.path.join(out_dir, name)
        plot(rows, path)
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
