#!/usr/bin/env python3
"""Draws tessera-bench-tradeoff's table as a Pareto plot: one panel per scene, trace time against
error (leaks and self-intersections per million rays; RMSE for the path-traced interior), each
knob a labelled point, the Pareto front (no other knob both faster and more accurate) joined.

Usage: pareto.py tradeoff.csv tradeoff.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.2 * len(scenes), 4.4))
    if len(scenes) == 1:
        axes = [axes]
    for ax, scene in zip(axes, scenes):
        points = []
        for r in rows:
            if r["scene"] != scene:
                continue
            rmse = float(r["rmse"])
            if rmse >= 0:
                error, label = rmse, "RMSE against the reference"
            elif r["knob"] == "reference":
                continue
            else:
                error = max(float(r["leaks_per_million"]), 0) + max(float(r["self_per_million"]), 0)
                label = "leaks + self-intersections per million rays"
            points.append((1e3 * float(r["trace_s"]), error, r["knob"]))
        if not points:
            continue
        floor = min([e for _, e, _ in points if e > 0] or [1.0]) / 10
        xs = [p[0] for p in points]
        ys = [max(p[1], floor) for p in points]
        ax.scatter(xs, ys, color="tab:blue")
        for x, y, (_, _, name) in zip(xs, ys, points):
            ax.annotate(name, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
        front = sorted(zip(xs, ys))
        best, line = float("inf"), []
        for x, y in front:
            if y < best:
                best = y
                line.append((x, y))
        ax.plot([p[0] for p in line], [p[1] for p in line], color="tab:orange", linewidth=1)
        ax.set_yscale("log")
        ax.set_title(scene, fontsize=10)
        ax.set_xlabel("trace time, ms (median)")
        ax.set_ylabel(label + " (0 drawn at the floor)", fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(dst, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
