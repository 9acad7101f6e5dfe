#!/usr/bin/env python3
"""Table I of the paper for generated sequences: object-map metrics per sequence and mode.

Usage:
  tools/object_table.py [--build build] [--modes off,visibility,paper,improved]
                        [--poses gt | --slam-runs DIR] [--out DIR] SEQUENCE_DIR...

For each sequence folder written by ocg_synth, runs the object layer in pose-given mode
(`ocg_slam objects`) once per OCG mode and scores the result with `ocg_eval objects`
(SPEC 4). Poses: the ground truth (default), or with --slam-runs the CameraTrajectory.txt
of an `ocg_slam run` per sequence (DIR/<sequence name>/), in which case the objects are
aligned to the ground truth through the trajectory (Sim(3)) before scoring.
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


def run(command):
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        sys.exit("failed: %s\n%s%s" % (" ".join(command), result.stdout, result.stderr))
    return result.stdout


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sequences", nargs="+", help="sequence folders written by ocg_synth")
    parser.add_argument("--build", default="build", help="build folder (default: build)")
    parser.add_argument("--modes", default="off,visibility,paper,improved",
                        help="OCG modes, comma-separated")
    parser.add_argument("--slam-runs", help="folder of ocg_slam run outputs, one per sequence")
    parser.add_argument("--settings", help="settings file (default: the sequence's camera.yaml)")
    parser.add_argument("--out", help="keep the runs and table.md here (default: a temp folder)")
    args = parser.parse_args()
    tools = os.path.join(args.build, "tools")
    out = args.out or tempfile.mkdtemp(prefix="ocg_object_table_")
    os.makedirs(out, exist_ok=True)
    modes = args.modes.split(",")
    lines = ["| sequence | mode | Corr.S | Unident.S | Redun.S (dup+spur) | Corr.M | Delet.S "
             "| Unident.M | Acc | Prec | Recall |", "|---" * 11 + "|"]
    for sequence in args.sequences:
        name = os.path.basename(os.path.normpath(sequence))
        groundtruth = os.path.join(sequence, "groundtruth.txt")
        trajectory = groundtruth
        if args.slam_runs:
            trajectory = os.path.join(args.slam_runs, name, "CameraTrajectory.txt")
        settings = args.settings or os.path.join(sequence, "camera.yaml")
        truth = None
        for mode in modes:
            run_dir = os.path.join(out, name, mode)
            run([os.path.join(tools, "ocg_slam"), "objects", "--trajectory", trajectory,
                 "--detections", os.path.join(sequence, "detections"), "--frames",
                 os.path.join(sequence, "rgb.txt"), "--settings", settings, "--mode", mode,
                 "--out", run_dir, "--log-level", "warn"])
            evaluate = [os.path.join(tools, "ocg_eval"), "objects", "--gt",
                        os.path.join(sequence, "objects_gt.json"), "--run", run_dir, "--json"]
            if args.slam_runs:
                # Objects were mapped in the SLAM frame: align through the trajectory. The
                # run folder of `ocg_slam objects` holds no trajectory, so point at the
                # SLAM run's.
                link = os.path.join(run_dir, "CameraTrajectory.txt")
                if os.path.lexists(link):
                    os.remove(link)
                os.symlink(os.path.abspath(trajectory), link)
                evaluate += ["--groundtruth", groundtruth]
            m = json.loads(run(evaluate))
            truth = m
            lines.append("| %s | %s | %d | %d | %d (%d+%d) | %d | %d | %d | %.3f | %.3f | %.3f |" % (
                name, mode, m["corr_s"], m["unident_s"], m["redun_s"], m["redun_duplicates"],
                m["redun_spurious"], m["corr_m"], m["delet_s"], m["unident_m"], m["acc"],
                m["prec"], m["recall"]))
        lines.append("| %s | GT | %d | 0 | 0 | %d | 0 | 0 | - | - | - |" % (
            name, truth["gt_static"], truth["gt_outdated"]))
    table = "\n".join(lines) + "\n"
    with open(os.path.join(out, "table.md"), "w") as handle:
        handle.write(table)
    print(table)
    print("runs and table.md in %s" % out, file=sys.stderr)


if __name__ == "__main__":
    main()
