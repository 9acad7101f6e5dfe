#!/usr/bin/env python3
"""Draws what `ocg_eval ate --plot F.png` computed: the aligned trajectories (top view)
and the per-axis error of each associated pair over time, like evo's plots.

Usage: ocg_plot_ate.py DATA.json OUT.png
DATA.json (written by ocg_eval): alignment, scale, rmse, count, reference and estimate
as [t, x, y, z] rows (the estimate already aligned into the ground truth's frame, metres),
errors as [t, ex, ey, ez, |e|] rows. OUT.png is 1200 x 700 pixels, written whole or not
at all. Exit status 2 when matplotlib is missing (Debian: python3-matplotlib).
"""
import json
import os
import sys

WIDTH_IN, HEIGHT_IN, DPI = 12, 7, 100


def load_pyplot():
    try:
        import matplotlib
    except ImportError as error:
        print("ocg_plot_ate: matplotlib is missing (%s): install python3-matplotlib "
              "(Debian), or set OCG_PYTHON to a python3 that has it" % error, file=sys.stderr)
        sys.exit(2)
    matplotlib.use("Agg")  # files only: no display needed
    import matplotlib.pyplot as pyplot
    return pyplot


def top_view_axes(rows):
    """The two world axes along which the ground truth spreads most (the view from above
    for a camera moving over a floor, whichever axis is up)."""
    spans = []
    for axis in range(3):
        values = [row[1 + axis] for row in rows]
        spans.append(max(values) - min(values) if values else 0.0)
    first, second = sorted(sorted(range(3), key=lambda axis: -spans[axis])[:2])
    return first, second


def draw(data, path):
    pyplot = load_pyplot()
    names = "xyz"
    reference, estimate, errors = data["reference"], data["estimate"], data["errors"]
    a, b = top_view_axes(reference)
    figure = pyplot.figure(figsize=(WIDTH_IN, HEIGHT_IN), dpi=DPI)
    grid = figure.add_gridspec(4, 2, width_ratios=[1.15, 1.0], hspace=0.35, wspace=0.25)
    top = figure.add_subplot(grid[:, 0])
    top.plot([r[1 + a] for r in reference], [r[1 + b] for r in reference], "--",
             color="0.35", linewidth=1.2, label="ground truth")
    top.plot([r[1 + a] for r in estimate], [r[1 + b] for r in estimate], "-",
             color="tab:blue", linewidth=1.2, label="estimate (aligned)")
    if estimate:
        top.plot(estimate[0][1 + a], estimate[0][1 + b], "o", color="tab:green", label="start")
    top.set_xlabel("%s [m]" % names[a])
    top.set_ylabel("%s [m]" % names[b])
    top.set_aspect("equal", adjustable="datalim")
    top.grid(True, linewidth=0.4)
    top.legend(loc="best", fontsize=9)
    top.set_title("top view, %s alignment (scale %.4f)" % (data["alignment"], data["scale"]))
    times = [row[0] - errors[0][0] for row in errors] if errors else []
    for index, label in enumerate(["x", "y", "z", "|e|"]):
        axis = figure.add_subplot(grid[index, 1])
        axis.plot(times, [row[1 + index] for row in errors], linewidth=1.0,
                  color="tab:red" if index == 3 else "tab:blue")
        axis.axhline(0.0, color="0.6", linewidth=0.6)
        if index == 3:
            axis.axhline(data["rmse"], color="0.2", linestyle=":", linewidth=1.0,
                         label="RMSE %.4f m" % data["rmse"])
            axis.legend(loc="upper right", fontsize=8)
            axis.set_xlabel("time since the first pair [s]")
        axis.set_ylabel("%s error [m]" % label if index < 3 else "|e| [m]", fontsize=9)
        axis.grid(True, linewidth=0.4)
    figure.suptitle("ATE: %d pairs, RMSE %.4f m" % (data["count"], data["rmse"]))
    temporary = path + ".tmp.png"
    try:
        figure.savefig(temporary, dpi=DPI)
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: ocg_plot_ate.py DATA.json OUT.png")
    with open(sys.argv[1]) as handle:
        data = json.load(handle)
    draw(data, sys.argv[2])


if __name__ == "__main__":
    main()
