#!/usr/bin/env python3
"""Trajectory accuracy and timing of `ocg_slam run` per sequence, loop closing on and off.

Usage:
  tools/slam_table.py [--build build] [--out DIR] [--reuse] [--detections] SEQUENCE_DIR...

For each sequence folder (TUM format with groundtruth.txt, e.g. written by ocg_synth),
runs `ocg_slam run` twice, with `LoopClosing.enabled` true and false (the sequence's
camera.yaml plus that one key), into OUT/<name>/lc_on and OUT/<name>/lc_off, and scores
both with `ocg_eval ate --align sim3` (every tracked frame, and the keyframes). With
--reuse, a run folder that already holds run.json is scored as it is; with --detections,
the runs map objects too (SEQUENCE/detections). Prints a Markdown table and writes it to
OUT/slam_table.md. Needs Python 3 only.
"""
import argparse
import json
import os
import sys
import tempfile

from object_table import run, write_table  # tools/ is on the path: the script's own folder


def ate(tools, groundtruth, trajectory):
    output = run([os.path.join(tools, "ocg_eval"), "ate", "--gt", groundtruth, "--est",
                  trajectory, "--align", "sim3", "--json"])
    return json.loads(output)["rmse"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sequences", nargs="+", help="sequence folders with groundtruth.txt")
    parser.add_argument("--build", default="build", help="build folder (default: build)")
    parser.add_argument("--out", help="keep the runs and slam_table.md here (default: a temp folder)")
    parser.add_argument("--reuse", action="store_true", help="score existing runs as they are")
    parser.add_argument("--detections", action="store_true", help="map objects too")
    args = parser.parse_args()
    tools = os.path.join(args.build, "tools")
    out = args.out or tempfile.mkdtemp(prefix="ocg_slam_table_")
    os.makedirs(out, exist_ok=True)
    lines = ["| sequence | loop closing | frames | tracked | keyframes | loops | ATE frames "
             "| ATE keyframes | tracking median | local mapping median / p95 |",
             "|---" * 10 + "|"]
    for sequence in args.sequences:
        name = os.path.basename(os.path.normpath(sequence))
        groundtruth = os.path.join(sequence, "groundtruth.txt")
        for enabled in (False, True):
            run_dir = os.path.join(out, name, "lc_on" if enabled else "lc_off")
            if not (args.reuse and os.path.exists(os.path.join(run_dir, "run.json"))):
                settings = os.path.join(out, name, "settings_lc_%s.yaml" % ("on" if enabled else "off"))
                os.makedirs(os.path.dirname(settings), exist_ok=True)
                with open(os.path.join(sequence, "camera.yaml")) as source, open(settings, "w") as target:
                    target.write(source.read())
                    target.write("\nLoopClosing:\n  enabled: %s\n" % ("true" if enabled else "false"))
                command = [os.path.join(tools, "ocg_slam"), "run", "--settings", settings,
                           "--sequence", sequence, "--out", run_dir, "--snapshots", "none",
                           "--log-level", "warn"]
                if args.detections:
                    command += ["--detections", os.path.join(sequence, "detections")]
                print("%s, loop closing %s: ocg_slam run" % (name, "on" if enabled else "off"),
                      file=sys.stderr)
                run(command)
            report = json.load(open(os.path.join(run_dir, "run.json")))
            timing = report["timing"]
            loops = len(report.get("loop_closing", {}).get("loops", []))
            lines.append("| %s | %s | %d | %d | %d | %d | %.1f mm | %.1f mm | %.1f ms | %.1f / %.1f ms |" % (
                name, "on" if enabled else "off", report["frames"], report["frames_tracked"],
                report["keyframes"], loops,
                1000 * ate(tools, groundtruth, os.path.join(run_dir, "CameraTrajectory.txt")),
                1000 * ate(tools, groundtruth, os.path.join(run_dir, "KeyFrameTrajectory.txt")),
                timing["tracking_per_frame"]["median_ms"],
                timing["local_mapping_per_keyframe"]["median_ms"],
                timing["local_mapping_per_keyframe"]["p95_ms"]))
    write_table(out, "slam_table.md", lines)


if __name__ == "__main__":
    main()
