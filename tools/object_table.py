#!/usr/bin/env python3
"""Table I of the paper for generated sequences: object-map metrics per sequence and mode.

Usage:
  tools/object_table.py [--build build] [--modes off,visibility,paper,improved]
                        [--slam-runs DIR | --slam [--reuse]] [--out DIR] SEQUENCE_DIR...

For each sequence folder written by ocg_synth, runs the object layer once per OCG mode
and scores the result with `ocg_eval objects` (SPEC 4). Three sources of poses:
  default       pose-given mode (`ocg_slam objects`) on the ground-truth poses;
  --slam-runs   pose-given mode on the CameraTrajectory.txt of an earlier `ocg_slam run`
                per sequence (DIR/<sequence name>/): SLAM's final poses, after the fact;
  --slam        the whole pipeline, `ocg_slam run --detections --modes M1,M2,...` (images,
                SLAM, objects from SLAM's poses and map points as it runs), into
                OUT/<name>/<M>/: one SLAM run per sequence feeds one object layer per
                mode (SLAM never reads the objects; in sequential mode each mode's files
                are byte for byte those of a run of its own); with --reuse, the modes
                whose folder already holds run.json are scored as they are.
With SLAM poses the objects are aligned to the ground truth through the trajectory
(Sim(3)) before scoring.
Prints a Markdown table (and writes it to OUT/table.md with every run's files).
Needs Python 3 only.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

COLUMNS = ["corr_s", "unident_s", "redun_s", "corr_m", "delet_s", "unident_m"]
# Table I's columns, here and in the batch's tables (eval/collect.py).
TABLE_I_HEADER = ["Corr.S", "Unident.S", "Redun.S (dup+spur)", "Corr.M", "Delet.S", "Unident.M",
                  "Acc", "Prec", "Recall"]


def table_header(first_columns, columns):
    """A Markdown table's header and rule lines."""
    names = list(first_columns) + list(columns)
    return ["| " + " | ".join(names) + " |", "|---" * len(names) + "|"]


def run(command):
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        sys.exit("failed: %s\n%s%s" % (" ".join(command), result.stdout, result.stderr))
    return result.stdout


def write_table(out, name, lines):
    """Writes the table's lines to OUT/name and prints it, and where the runs are."""
    table = "\n".join(lines) + "\n"
    with open(os.path.join(out, name), "w") as handle:
        handle.write(table)
    print(table)
    print("runs and %s in %s" % (name, out), file=sys.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sequences", nargs="+", help="sequence folders written by ocg_synth")
    parser.add_argument("--build", default="build", help="build folder (default: build)")
    parser.add_argument("--modes", default="off,visibility,paper,improved",
                        help="OCG modes, comma-separated")
    parser.add_argument("--slam-runs", help="folder of ocg_slam run outputs, one per sequence")
    parser.add_argument("--slam", action="store_true",
                        help="run the whole pipeline (ocg_slam run --detections) per mode")
    parser.add_argument("--reuse", action="store_true",
                        help="with --slam: score existing runs (OUT/<name>/<mode>/run.json)")
    parser.add_argument("--settings", help="settings file (default: the sequence's camera.yaml)")
    parser.add_argument("--include-never-in-view", action="store_true",
                        help="count static objects the sequence never shows as ground truth "
                             "(ocg_eval objects --include-never-in-view)")
    parser.add_argument("--out", help="keep the runs and table.md here (default: a temp folder)")
    args = parser.parse_args()
    if args.slam and args.slam_runs:
        parser.error("--slam runs SLAM itself: give --slam or --slam-runs, not both")
    tools = os.path.join(args.build, "tools")
    out = args.out or tempfile.mkdtemp(prefix="ocg_object_table_")
    os.makedirs(out, exist_ok=True)
    modes = args.modes.split(",")
    lines = table_header(["sequence", "mode"], TABLE_I_HEADER)
    for sequence in args.sequences:
        name = os.path.basename(os.path.normpath(sequence))
        groundtruth = os.path.join(sequence, "groundtruth.txt")
        trajectory = groundtruth
        if args.slam_runs:
            trajectory = os.path.join(args.slam_runs, name, "CameraTrajectory.txt")
        settings = args.settings or os.path.join(sequence, "camera.yaml")
        truth = None
        if args.slam:
            missing = [mode for mode in modes if not (
                args.reuse and os.path.exists(os.path.join(out, name, mode, "run.json")))]
            if missing:
                print("%s, %s: ocg_slam run" % (name, ",".join(missing)), file=sys.stderr)
                run([os.path.join(tools, "ocg_slam"), "run", "--settings", settings,
                     "--sequence", sequence, "--detections",
                     os.path.join(sequence, "detections"), "--modes", ",".join(missing),
                     "--out", os.path.join(out, name), "--log-level", "warn"])
        for mode in modes:
            run_dir = os.path.join(out, name, mode)
            evaluate = [os.path.join(tools, "ocg_eval"), "objects", "--gt",
                        os.path.join(sequence, "objects_gt.json"), "--run", run_dir, "--json"]
            if args.include_never_in_view:
                evaluate.append("--include-never-in-view")
            if args.slam:
                evaluate += ["--groundtruth", groundtruth]
            else:
                # A sequence written with `ocg_synth --detections-only` has no rgb.txt: the
                # detection files' names give the same frames.
                frames = os.path.join(sequence, "rgb.txt")
                run([os.path.join(tools, "ocg_slam"), "objects", "--trajectory", trajectory,
                     "--detections", os.path.join(sequence, "detections")] +
                    (["--frames", frames] if os.path.exists(frames) else []) +
                    ["--settings", settings, "--mode", mode, "--out", run_dir,
                     "--log-level", "warn"])
            if args.slam_runs and not args.slam:
                # Objects were mapped in the SLAM frame: align through the SLAM run's whole
                # trajectory, not the given poses `ocg_slam objects` keeps of its frames
                # and OCG keyframes (ocg_eval objects would take KeyFrameTrajectory.txt first).
                link = os.path.join(run_dir, "CameraTrajectory.txt")
                for stale in (link, os.path.join(run_dir, "KeyFrameTrajectory.txt")):
                    if os.path.lexists(stale):
                        os.remove(stale)
                os.symlink(os.path.abspath(trajectory), link)
                evaluate += ["--groundtruth", groundtruth]
            m = json.loads(run(evaluate))
            truth = m
            lines.append("| %s | %s | %d | %d | %d (%d+%d) | %d | %d | %d | %.3f | %.3f | %.3f |" % (
                name, mode, m["corr_s"], m["unident_s"], m["redun_s"], m["redun_duplicates"],
                m["redun_spurious"], m["corr_m"], m["delet_s"], m["unident_m"], m["acc"],
                m["prec"], m["recall"]))
        unseen = truth.get("gt_never_in_view", 0)
        lines.append("| %s | GT | %d%s | 0 | 0 | %d | 0 | 0 | - | - | - |" % (
            name, truth["gt_static"],
            " (+%d never in view)" % unseen if unseen else "", truth["gt_outdated"]))
    write_table(out, "table.md", lines)


if __name__ == "__main__":
    main()
