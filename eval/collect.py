"""Collects the batch's scores into Table I (object metrics) and Table II (ATE), as
Markdown and CSV, with the median and the spread (min-max) over the repeats of each
system, and plots the ATE per sequence and system.

Usage: collect.py OUT/batch.json
Writes OUT/table_I.md, table_I.csv, table_II.md, table_II.csv, objects.md (what each
system's object map holds, for every sequence with detections, ground truth or not),
timing.md (tracking time: the one figure that depends on the machine), failed_runs.csv,
plots/ate.png. The Markdown layout of Table I is tools/object_table.py's,
with the moves reported right (a `moved` entry in changes.json towards the right object)
after it.

A run whose job failed (or never ran: the batch stopped first) has no score: it is counted
in its system's `failed` column and listed under the tables and in failed_runs.csv with the
stage that failed, the last line of that stage's log and, on Slurm, the job id.
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


def last_log_line(log):
    """The log's last line that says something (progress lines end in carriage returns), and
    the Slurm job id the job wrote at its top, if any."""
    with open(log, errors="replace") as handle:
        lines = handle.read().replace("\r", "\n").splitlines()
    job = next((l.split()[-1] for l in lines if l.startswith("# slurm job ")), "")
    said = [l.strip() for l in lines if l.strip() and not l.startswith("# ")]
    return (said[-1] if said else "(empty log)"), job


def run_failure(batch, run):
    """{stage, message, slurm_job, log} for a run without a score: the first of its jobs
    (sequence, settings, run, score) whose output is missing."""
    out = batch["out"]
    sequence, variant, mode, rest = run.split("/")
    execution = rest.rsplit("-", 1)[0]
    generated = any(s["name"] == sequence and s["generated"] for s in batch["sequences"])
    stages = [("sequence", os.path.join(out, "sequences", sequence),
               os.path.join(out, "logs", "sequences", sequence + ".log"))] if generated else []
    if any(s["name"] == sequence and s.get("detect") is not None for s in batch["sequences"]):
        stages.append(("detect", os.path.join(out, "detections", sequence),
                       os.path.join(out, "logs", "detections", sequence + ".log")))
    settings = os.path.join(sequence, "%s-%s" % (variant, execution))
    stages += [("settings", os.path.join(out, "settings", settings + ".yaml"),
                os.path.join(out, "logs", "settings", settings + ".log")),
               ("run", os.path.join(out, "runs", run), os.path.join(out, "logs", "runs", run + ".log")),
               ("score", os.path.join(out, "scores", run + ".json"),
                os.path.join(out, "logs", "scores", run + ".log"))]
    for stage, output, log in stages:
        if os.path.exists(output):
            continue
        if not os.path.exists(log):
            return {"stage": stage, "message": "not run (the batch stopped before it)",
                    "slurm_job": "", "log": ""}
        message, job = last_log_line(log)
        return {"stage": stage, "message": message, "slurm_job": job,
                "log": os.path.relpath(log, out)}
    return {"stage": "score", "message": "no score", "slurm_job": "", "log": ""}


def load_scores(batch):
    """{(sequence, variant, mode, execution): [score of each repeat]} in the batch's order,
    and {run: failure} of the runs without a score (their entry there is {"failed": ...})."""
    systems, failures = {}, {}
    for run in batch["runs"]:
        sequence, variant, mode, rest = run.split("/")
        execution = rest.rsplit("-", 1)[0]
        path = os.path.join(batch["out"], "scores", run + ".json")
        if os.path.exists(path):
            with open(path) as handle:
                score = json.load(handle)
        else:
            failures[run] = run_failure(batch, run)
            score = {"failed": failures[run]}
        systems.setdefault((sequence, variant, mode, execution), []).append(score)
    return systems, failures


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


def table_one(batch, systems, failures):
    lines = table_header(SYSTEM_KEYS + ["runs"], TABLE_I_HEADER + ["Moves right"])
    rows = []
    keys = list(systems)
    ground_truth = {}  # sequence -> a score's objects (its gt_static, gt_outdated)
    for index, key in enumerate(keys):
        scores = systems[key]
        measured = [s["objects"] for s in scores if s.get("objects")]
        if measured:
            ground_truth[key[0]] = measured[0]
            cells, numbers = [], []
            for metric in METRICS:
                text, values = spread([m[metric] for m in measured], metric in RATIOS)
                if metric == "redun_s":
                    text += " (%g+%g)" % (
                        statistics.median(m["redun_duplicates"] for m in measured),
                        statistics.median(m["redun_spurious"] for m in measured))
                cells.append(text)
                numbers += values
            # Of the ground truth's moves, those the run's change log reports as moves to
            # the right object (ocg_eval objects: moves_right of gt_moves).
            moves, _ = spread([m.get("moves_right", 0) for m in measured], False)
            gt_moves = measured[0].get("gt_moves", 0)
            cells.append("%s of %d" % (moves, gt_moves) if gt_moves else "-")
            lines.append("| " + " | ".join(list(key) + [str(len(measured))] + cells) + " |")
            rows.append(list(key) + [len(measured)] + numbers +
                        [statistics.median(m.get("moves_right", 0) for m in measured), gt_moves,
                         measured[0]["gt_static"], measured[0]["gt_outdated"]])
        elif key[2] != "slam" and any(s.get("failed") for s in scores):
            # Every run of the system failed: a row that says so, not a missing one.
            lines.append("| " + " | ".join(list(key) + ["0"] + ["failed"] * (len(METRICS) + 1)) +
                         " |")
            rows.append(list(key) + [0] + [""] * (3 * len(METRICS) + 4))
        # (no objects for this system otherwise: a sequence without detections)
        last_of_sequence = index + 1 == len(keys) or keys[index + 1][0] != key[0]
        if last_of_sequence and key[0] in ground_truth:
            # The ground truth's row, as tools/object_table.py writes it.
            gt = ground_truth[key[0]]
            lines.append("| %s | | GT | | | %d | 0 | 0 | %d | 0 | 0 | - | - | - | %d |" % (
                key[0], gt["gt_static"], gt["gt_outdated"], gt.get("gt_moves", 0)))
    header = SYSTEM_KEYS + ["runs"] + ["%s_%s" % (m, s) for m in METRICS
                                       for s in ("median", "min", "max")] + [
        "moves_right_median", "gt_moves", "gt_static", "gt_outdated"]
    write_csv(os.path.join(batch["out"], "table_I.csv"), header, rows)
    if not rows:
        # A header alone reads as a broken batch: say why there is no row.
        lines.append("")
        lines.append("No row: Table I scores object maps against an object ground truth, which "
                     "only generated sequences and sequences with `objects_gt:` have. What the "
                     "object maps hold is in objects.md.")
    write_table(batch["out"], "table_I.md", lines + failure_lines(failures))


def failure_lines(failures):
    """Markdown list of the failed runs, under the tables."""
    if not failures:
        return []
    lines = ["", "Failed runs (no score; run the batch again to retry them):", ""]
    for run, failure in failures.items():
        job = " (Slurm job %s)" % failure["slurm_job"] if failure["slurm_job"] else ""
        log = " [%s]" % failure["log"] if failure["log"] else ""
        lines.append("- %s: %s failed%s: `%s`%s" % (run, failure["stage"], job,
                                                     failure["message"], log))
    return lines


def write_failures(batch, failures):
    write_csv(os.path.join(batch["out"], "failed_runs.csv"),
              ["run", "stage", "slurm_job", "last_log_line", "log"],
              [[run, f["stage"], f["slurm_job"], f["message"], f["log"]]
               for run, f in failures.items()])


def table_two(batch, systems, failures):
    lines = table_header(SYSTEM_KEYS + ["runs", "failed"],
                         ["frames", "tracked frames", "keyframes", "loops closed",
                          "ATE RMSE [mm]", "Sim(3) scale"])
    rows, series = [], []
    for key, scores in systems.items():
        good = [s for s in scores if s.get("ate")]
        failed = len(scores) - len(good)
        ate = [1000.0 * s["ate"]["rmse"] for s in good]
        tracked = [s["frames_tracked"] for s in scores if s.get("frames_tracked") is not None]
        keyframes = [s["keyframes"] for s in scores if s.get("keyframes") is not None]
        scale = [s["ate"]["scale"] for s in good]
        frames = [s["frames"] for s in scores if s.get("frames") is not None]
        loops = [s["loops"] for s in scores if s.get("loops") is not None]
        cells = [spread(frames, False)[0], spread(tracked, False)[0],
                 spread(keyframes, False)[0], spread(loops, False)[0]]
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
    write_table(batch["out"], "table_II.md", lines + failure_lines(failures))
    return series


def timing_table(batch, systems):
    """OUT/timing.md: tracking time per frame (wall clock, the median over each run's frames).
    Apart from the tables, which are the same on every machine and every re-run: this
    depends on the machine and on what else it runs."""
    lines = table_header(SYSTEM_KEYS + ["runs"], ["tracking [ms/frame]"])
    for key, scores in systems.items():
        tracking = [round(s["tracking_ms"], 1) for s in scores if s.get("tracking_ms") is not None]
        if tracking:
            lines.append("| " + " | ".join(list(key) + [str(len(tracking)),
                                                         spread(tracking, False)[0]]) + " |")
    write_table(batch["out"], "timing.md", lines)


def run_object_map(run_dir):
    """What one run's object map holds: {objects, classes: {class: count}, removed, moved},
    or None when the run wrote no object map. A removal undone by a later `restored` entry
    of the same object (OCG.mode restore) is not counted (docs/objects.md, Outputs)."""
    try:
        with open(os.path.join(run_dir, "objects.json")) as handle:
            objects = json.load(handle)["objects"]
        with open(os.path.join(run_dir, "changes.json")) as handle:
            changes = json.load(handle)["changes"]
    except (OSError, ValueError, KeyError):
        return None
    classes = {}
    for entry in objects:
        classes[entry["class"]] = classes.get(entry["class"], 0) + 1
    removals = {}  # object id -> its removal entries' types, oldest first
    for change in changes:
        if change["type"] in ("removed", "moved"):
            removals.setdefault(change["object_id"], []).append(change["type"])
        elif change["type"] == "restored" and removals.get(change["object_id"]):
            removals[change["object_id"]].pop()
    kinds = [kind for entries in removals.values() for kind in entries]
    return {"objects": len(objects), "classes": classes, "removed": len(kinds),
            "moved": kinds.count("moved")}


def object_maps(batch, systems):
    """OUT/objects.md: for every system that mapped objects, the map's size and classes, and
    what change detection removed (of that, reported as moves). On a sequence without an
    object ground truth (real video) this is the object-map result there is."""
    lines = table_header(SYSTEM_KEYS + ["runs"],
                         ["objects", "classes (first run)", "removed by the OCG",
                          "of them moves"])
    for key in systems:
        if key[2] == "slam":
            continue
        prefix = os.path.join(batch["out"], "runs", *key[:3])
        maps = []
        for run in batch["runs"]:
            sequence, variant, mode, rest = run.split("/")
            if (sequence, variant, mode, rest.rsplit("-", 1)[0]) == key:
                found = run_object_map(os.path.join(prefix, rest))
                if found is not None:
                    maps.append(found)
        if not maps:
            continue
        classes = ", ".join("%s %d" % (name, count) for name, count in
                            sorted(maps[0]["classes"].items(), key=lambda c: (-c[1], c[0])))
        cells = [spread([m[field] for m in maps], False)[0]
                 for field in ("objects", "removed", "moved")]
        lines.append("| " + " | ".join(list(key) + [str(len(maps)), cells[0], classes or "-",
                                                     cells[1], cells[2]]) + " |")
    write_table(batch["out"], "objects.md", lines)


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
    systems, failures = load_scores(batch)
    table_one(batch, systems, failures)
    series = table_two(batch, systems, failures)
    object_maps(batch, systems)
    timing_table(batch, systems)
    write_failures(batch, failures)
    plot_ate(os.path.join(batch["out"], "plots", "ate.png"), series)
    if failures:
        print("collect.py: %d of %d runs failed (listed under the tables and in %s)" % (
            len(failures), len(batch["runs"]),
            os.path.join(batch["out"], "failed_runs.csv")), file=sys.stderr)
        for run, failure in failures.items():
            print("  %s: %s: %s" % (run, failure["stage"], failure["message"]), file=sys.stderr)
        sys.exit(3)


if __name__ == "__main__":
    main()
