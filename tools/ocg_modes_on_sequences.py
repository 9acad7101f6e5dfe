#!/usr/bin/env python3
"""Runs every OCG mode on the oracle streams of generated sequences and scores the removals.

Usage: tools/ocg_modes_on_sequences.py [--build build] SEQUENCE_DIR...

For each sequence folder written by ocg_synth (oracle_observations.jsonl and
objects_gt.json inside), runs build/tools/ocg_replay in each mode and counts, from the
ground truth:
  moved removed    map objects at a place an object left (moved or removed) that are no
                   longer in the map at the end (Corr.M), out of those ever observed;
  static removed   map objects at a place where an object still is at the end that are
                   not in the map at the end (Delet.S), out of those ever observed. An
                   object removed and then seen again re-enters the map (SPEC 3.1), so
                   it counts as kept if it is back by the end.
Oracle map ids are object id * 100 + pose index (docs/synthetic.md). Needs Python 3 only.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

MODES = ["paper", "fallback", "in_image", "guard", "view", "improved"]


def score(sequence, graph_path):
    truth = json.load(open(os.path.join(sequence, "objects_gt.json")))
    observed = set()
    for line in open(os.path.join(sequence, "oracle_observations.jsonl")):
        observed.update(json.loads(line)["observed"])
    live = {node["id"] for node in json.load(open(graph_path))["nodes"]}
    removed = observed - live
    outdated, current = set(), set()
    for obj in truth["objects"]:
        # A later visit's history starts with the previous visit's pose ("session"): the
        # oracle numbers only the visit's own poses.
        history = [pose for pose in obj["history"] if "session" not in pose]
        for index, pose in enumerate(history):
            if not pose["present"]:
                continue
            map_id = obj["id"] * 100 + index
            (current if index == len(history) - 1 else outdated).add(map_id)
    outdated &= observed
    current &= observed
    return len(outdated & removed), len(outdated), len(current & removed), len(current)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("sequences", nargs="+")
    args = parser.parse_args()
    replay = os.path.join(args.build, "tools", "ocg_replay")
    print("| sequence | mode | moved removed (Corr.M) | static removed (Delet.S) |")
    print("|---|---|---|---|")
    for sequence in args.sequences:
        for mode in MODES:
            with tempfile.TemporaryDirectory() as out:
                subprocess.run([replay, "--input", os.path.join(sequence, "oracle_observations.jsonl"),
                                "--out", out, "--mode", mode, "--log-level", "warn"],
                               check=True, stdout=subprocess.DEVNULL)
                moved, moved_total, static, static_total = score(sequence, os.path.join(out, "ocg.json"))
            print(f"| {os.path.basename(os.path.normpath(sequence))} | {mode} | {moved}/{moved_total} | "
                  f"{static}/{static_total} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
