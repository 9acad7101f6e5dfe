#!/usr/bin/python3
"""results_page: write the project's results page (docs/results.md) from an ocg_batch
output folder: the tables it collected and the commands that made them.

Usage:
  tools/results_page.py BATCH_OUT --config CONFIG.yaml [--out docs/results.md]

BATCH_OUT is the `out:` folder of a finished `ocg_batch CONFIG.yaml` (it holds batch.json,
table_I.md, table_II.md and objects.md). The page says which commit built the tools, when,
on what machine, and repeats the configuration, so that anyone can make the same tables
again. Nothing is measured here: every figure on the page is one the batch wrote. The
final snapshots of the runs that drew them (`snapshots: true` in the configuration) are
copied beside the page (--images, default images/results/ in the page's folder) and shown.
"""
import argparse
import datetime
import json
import os
import platform
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))

EXPLANATION = """\
A system is a sequence run with one settings variant, one OCG mode and one execution
(sequential or threaded); `slam` is a run without detections. Each cell is the median over
a system's runs, with the spread (min-max) in brackets when the runs differ; sequential
runs are byte-identical when repeated, so they run once.
"""

SLAM_NOTE = """\
Tracked frames, keyframes and loops closed as the run counted them (`run.json`); ATE RMSE
over every tracked frame after Sim(3) alignment (millimetres, [evaluation.md](evaluation.md))
and the alignment's scale.
"""

TIMING_NOTE = """\
Tracking time per frame (median over the run's frames, wall clock, feature extraction
included): unlike the tables above, it depends on the machine and on what else it was
running.
"""

TABLE_I_NOTE = """\
The paper's object-map table (SPEC 4, [objects.md](objects.md)), for the sequences with an
object ground truth: Corr.S static objects mapped where they are, Unident.S static objects
never mapped, Redun.S objects that are not there (duplicates + spurious), Corr.M moved
objects whose old place was cleared, Delet.S static objects wrongly removed, Unident.M
moved objects still mapped at their old place; Acc, Prec and Recall as the paper defines
them. Moves right: of the ground truth's moves, those the run's change log reports as a
move to the right object. The GT row gives the ground truth's counts.
"""

OBJECTS_NOTE = """\
What each object map holds at the end of the run (`objects.json`), and what change
detection removed from it (`changes.json`; a removal undone by a `restored` entry is not
counted), of which reported as moves. On real video there is no object ground truth: this
table is the result, and on a static scene nothing should have been removed.
"""


def fail(message):
    sys.exit("results_page: error: " + message)


def read(path, what):
    try:
        with open(path, encoding="utf-8") as handle:
            return handle.read()
    except OSError as error:
        fail("cannot read %s %s: %s (did `ocg_batch` finish?)" % (what, path, error.strerror))


def git_commit():
    try:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True).stdout.strip()
        return commit + (" with uncommitted changes" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown (not a git checkout)"


def relative(path):
    return os.path.relpath(path, ROOT) if path.startswith(ROOT + os.sep) else path


SNAPSHOTS = [("final_frame.png", "the last frame, its boxes and the cuboids"),
             ("final_objects.png", "the object map (cuboids coloured by OCG state)")]


def snapshot_section(batch, images_dir, page_dir):
    """Copies the final snapshots of every run that drew them into images_dir; returns the
    page's lines showing them (none when no run drew any)."""
    lines = []
    shown = {}  # picture bytes -> the run shown with them (two OCG modes that agree draw alike)
    for run in batch.get("runs", []):
        folder = os.path.join(batch["out"], "runs", run, "snapshots")
        found = [(name, what) for name, what in SNAPSHOTS
                 if os.path.isfile(os.path.join(folder, name))]
        if not found:
            continue
        lines += ["### %s" % run, ""]
        for name, what in found:
            with open(os.path.join(folder, name), "rb") as handle:
                picture = handle.read()
            if picture in shown:
                lines += ["%s: as %s's." % (what[0].upper() + what[1:], shown[picture]), ""]
                continue
            shown[picture] = run
            target = os.path.join(images_dir, run.replace("/", "_") + "_" + name)
            os.makedirs(images_dir, exist_ok=True)
            shutil.copyfile(os.path.join(folder, name), target)
            lines += ["![%s: %s](%s)" % (run, what, os.path.relpath(target, page_dir)), ""]
    if not lines:
        return []
    return ["## Snapshots", "",
            "The final snapshots of the runs that drew them (`snapshots: true`;",
            "[viewer.md](viewer.md)).", ""] + lines


def page(batch_out, config_path, images_dir=None, page_dir=None):
    batch = json.loads(read(os.path.join(batch_out, "batch.json"), "the resolved batch"))
    table_one = read(os.path.join(batch_out, "table_I.md"), "Table I").strip()
    table_two = read(os.path.join(batch_out, "table_II.md"), "Table II").strip()
    objects_path = os.path.join(batch_out, "objects.md")
    objects = read(objects_path, "the object maps").strip() if os.path.exists(objects_path) \
        else ""
    config = read(config_path, "the batch configuration").rstrip()
    sequences = ", ".join(s["name"] for s in batch.get("sequences", []))
    config_shown = relative(os.path.abspath(config_path))
    out_shown = relative(os.path.abspath(batch_out))
    lines = [
        "# Results",
        "",
        "<!-- Generated by tools/results_page.py from an ocg_batch output folder: edit the",
        "     batch configuration or the code, run the two commands below again. -->",
        "",
        "Measured with this repository's tools; every figure below was written by `ocg_batch`.",
        "Tools built from commit %s, Release build; tables collected on %s on a %d-core %s "
        "machine." % (git_commit(), datetime.date.today().isoformat(), os.cpu_count() or 1,
                      platform.machine()),
        "Sequences: %s; %d runs." % (sequences, len(batch.get("runs", []))),
        "",
        "```bash",
        "tools/ocg_batch %s --cores 2 --out %s" % (config_shown, out_shown),
        "tools/results_page.py %s --config %s --out docs/results.md" % (out_shown, config_shown),
        "```",
        "",
        EXPLANATION,
        "## Camera trajectory (Table II)",
        "",
        SLAM_NOTE,
        table_two,
        "",
        "## Object map against the ground truth (Table I)",
        "",
        TABLE_I_NOTE,
        table_one,
        "",
    ]
    if objects.count("\n") >= 2:  # a header, its rule and at least one row
        lines += ["## What each object map holds", "", OBJECTS_NOTE, objects, ""]
    timing_path = os.path.join(batch_out, "timing.md")
    if os.path.exists(timing_path):
        lines += ["## Speed", "", TIMING_NOTE, read(timing_path, "the timing table").strip(), ""]
    if images_dir is not None:
        lines += snapshot_section(batch, images_dir, page_dir)
    lines += [
        "## The configuration",
        "",
        "`%s`:" % config_shown,
        "",
        "```yaml",
        config,
        "```",
        "",
        "Measurements made while the system was developed, with their reasons and what did not",
        "work, are in the development log ([history/results-log.md](history/results-log.md)).",
        "",
    ]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(
        prog="results_page", description=__doc__.split("\n\n")[0].split(": ", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("batch_out", help="ocg_batch output folder (holds batch.json)")
    parser.add_argument("--config", required=True, help="the batch configuration it ran")
    parser.add_argument("--out", default="-", help="page to write (default: standard output)")
    parser.add_argument("--images", help="folder for the runs' snapshots (default: "
                        "images/results beside the page; none on standard output)")
    args = parser.parse_args()
    if args.out == "-":
        sys.stdout.write(page(args.batch_out, args.config))
        return
    page_dir = os.path.dirname(os.path.abspath(args.out))
    images = args.images or os.path.join(page_dir, "images", "results")
    text = page(args.batch_out, args.config, os.path.abspath(images), page_dir)
    temporary = args.out + ".tmp"
    with open(temporary, "w", encoding="utf-8") as handle:
        handle.write(text)
    os.replace(temporary, args.out)
    print("results_page: wrote %s" % args.out, file=sys.stderr)


if __name__ == "__main__":
    main()
