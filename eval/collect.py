"""Collects the batch's scores into Table I (object metrics) and Table II (ATE), as
Markdown and CSV, with the median and the spread (min-max) over the repeats of each
system, and plots the ATE per sequence and system.

Usage: collect.py OUT/batch.json
Writes OUT/table_I.md, table_I.csv, table_II.md, table_II.csv, plots/ate.png.
The Markdown layout of Table I is tools/object_table.py's.
"""
import csv
import json
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
# object_table.py: tools/ in the source tree, beside this script once installed.
sys.path[:0] = [os.path.join(HERE, "..", "tools"), HERE]
from object_table import TABLE_I_HEADER, table_header, write_table  # noqa: E402

METRICS = ["corr_s", "unident_s", "redun_s", "corr_m", "delet_s", "unident_m", "acc", "prec",
           "recall"]
RATIOS = {"acc", "prec", "recall"}
SYSTEM_KEYS = ["sequence", "variant", "mode", "execution"]


def load_scores(batch):
    """{(sequence, variant, mode, execution): [score of each repeat]} in the batch's order."""
    systems = {}
    for run in batch["runs"]:
        sequence, variant, mode, rest = run.split("/")
        execution = rest.rsplit("-", 1)[0]
        with open(os.path.join(batch["out"], "scores", run + ".json")) as handle:
            systems.setdefault((sequence, variant, mode, execution), []).append(json.load(handle))
    return systems


def spread(values, ratio):
    """'median (min-max)' for Markdown, and the three numbers for the CSV."""
    if not values:
        return "-", ["", "", ""]
    median, low, high = statistics.median(values), min(values), max(values)
    form = "%.3f" if ratio else "%g"
    text = form % median
    if high > low:
        text += " (" + form % low + "-" + form % high + ")"
    return text, [median, low, high]


def write_csv(path, header, rows):
    temporary = path + ".tmp"
    with open(temporary, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        writer.writerows(rows)
    os.replace(temporary, path)


def table_one(batch, systems):
    lines = table_header(SYSTEM_KEYS + ["runs"], TABLE_I_HEADER)
    rows = []
    last = list(systems)[-1] if systems else None
    for key, scores in systems.items():
        measured = [s["objects"] for s in scores if s.get("objects")]
        if not measured:
            continue  # no objects for this system (a sequence without detections)
        cells, numbers = [], []
        for metric in METRICS:
            text, values = spread([m[metric] for m in measured], metric in RATIOS)
            if metric == "redun_s":
                text += " (%g+%g)" % (statistics.median(m["redun_duplicates"] for m in measured),
                                      statistics.median(m["redun_spurious"] for m in measured))
            cells.append(text)
            numbers += values
        lines.append("| " + " | ".join(list(key) + [str(len(measured))] + cells) + " |")
        gt = measured[0]
        rows.append(list(key) + [len(measured)] + numbers + [gt["gt_static"], gt["gt_outdated"]])
        following = list(systems)[list(systems).index(key) + 1] if key != last else None
        if following is None or following[0] != key[0]:
            # The ground truth's row, as tools/object_table.py writes it.
            lines.append("| %s | | GT | | | %d | 0 | 0 | %d | 0 | 0 | - | - | - |" % (
                key[0], gt["gt_static"], gt["gt_outdated"]))
    header = SYSTEM_KEYS + ["runs"] + ["%s_%s" % (m, s) for m in METRICS
                                       for s in ("median", "min", "max")] + ["gt_static", "gt_outdated"]
    write_csv(os.path.join(batch["out"], "table_I.csv"), header, rows)
    write_table(batch["out"], "table_I.md", lines)


def table_two(batch, systems):
    lines = table_header(SYSTEM_KEYS + ["runs", "failed"],
                         ["tracked frames", "keyframes", "ATE RMSE [mm]", "Sim(3) scale"])
    rows, series = [], []
    for key, scores in systems.items():
        good = [s for s in scores if s.get("ate")]
        failed = len(scores) - len(good)
        ate = [1000.0 * s["ate"]["rmse"] for s in good]
        tracked = [s["frames_tracked"] for s in scores if s.get("frames_tracked") is not None]
        keyframes = [s["keyframes"] for s in scores if s.get("keyframes") is not None]
        scale = [s["ate"]["scale"] for s in good]
        cells = [spread(tracked, False)[0], spread(keyframes, False)[0]]
        ate_text, ate_numbers = spread(ate, False)
        if ate:
            ate_text, _ = spread([round(value, 2) for value in ate], False)
        cells += [ate_text, spread(scale, True)[0]]
        lines.append("| " + " | ".join(list(key) + [str(len(scores)), str(failed)] + cells) + " |")
        rows.append(list(key) + [len(scores), failed] + ate_numbers +
                    [statistics.median(tracked) if tracked else ""])
        series.append((key, ate))
    write_csv(os.path.join(batch["out"], "table_II.csv"),
              SYSTEM_KEYS + ["runs", "failed", "ate_median_mm", "ate_min_mm", "ate_max_mm",
                             "tracked_frames_median"], rows)
    write_table(batch["out"], "table_II.md", lines)
    return series


def plot_ate(path, series):
    """One panel per sequence: every run's ATE per system, the median as a bar."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot
    sequences = list(dict.fromkeys(key[0] for key, _ in series))
    figure, axes = pyplot.subplots(1, len(sequences), figsize=(max(6, 4.5 * len(sequences)), 4.5),
                                   dpi=100, squeeze=False)
    for axis, sequence in zip(axes[0], sequences):
        mine = [(key, values) for key, values in series if key[0] == sequence]
        for index, (key, values) in enumerate(mine):
            axis.plot([index] * len(values), values, "o", color="tab:blue", alpha=0.7)
            if values:
                axis.hlines(statistics.median(values), index - 0.3, index + 0.3, color="tab:red")
        axis.set_xticks(range(len(mine)))
        axis.set_xticklabels(["%s\n%s\n%s" % key[1:] for key, _ in mine], fontsize=8)
        axis.set_title(sequence)
        axis.set_ylabel("ATE RMSE [mm]")
        axis.set_ylim(bottom=0)
        axis.grid(True, axis="y", linewidth=0.4)
    figure.suptitle("ATE per sequence and system (dots: runs, red: median)")
    figure.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    temporary = path + ".tmp.png"
    figure.savefig(temporary)
    os.replace(temporary, path)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    with open(sys.argv[1]) as handle:
        batch = json.load(handle)
    systems = load_scores(batch)
    table_one(batch, systems)
    series = table_two(batch, systems)
    plot_ate(os.path.join(batch["out"], "plots", "ate.png"), series)


if __name__ == "__main__":
    main()
