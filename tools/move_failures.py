#!/usr/bin/env python3
"""Each ground-truth move of a generated sequence, and why a run reported it right or not.

Usage:
  tools/move_failures.py [--tau-doubt 50] RUN_DIR SEQUENCE_DIR [RUN_DIR SEQUENCE_DIR ...]

For each pair (a run folder of `ocg_slam objects` on the sequence's ground-truth poses, and
the `ocg_synth` folder it ran on; a SLAM run's objects are in its own frame and scale, which
this tool does not align), every move of `objects_gt.json` (an object
present at one place, then at another; a new place no frame shows is left out, as
`ocg_eval objects` leaves it out of gt_moves) gets one kind. A run object is near a place
as for `ocg_eval objects`: of the place's class, its centre within half the object's
largest extent. Run objects are the live ones of `objects.json` and the `moved` and
`removed` entries of `changes.json` (not a removal a `restored` entry undid).
  right             a `moved` entry from near the old place to near the new one (what
                    ocg_eval counts as moves_right);
  paired wrong      a `moved` entry from near the old place to elsewhere; "swapped with N"
                    when to the new place of move N, of the same class, whose old place's
                    object went to this new place (two objects of one class moved while the
                    camera was away: without appearance, times and places cannot tell them
                    apart), "to the new place of N" when only the first holds;
  removed, unpaired a `removed` entry near the old place, no move;
  still mapped      a live object near the old place at the end, with its OCG state and
                    DoubtValue from `ocg.json` ("suspicious, doubt 109 > 50": the OCG removes
                    such an object once the camera leaves its neighbours again, and the
                    sequence ended first);
  never mapped      no run object was ever near the old place.
Prints one line per move and the count of each kind. Needs Python 3 only.
"""
import argparse
import collections
import json
import math
import os
import sys

STATES = {1: "observed", 2: "recently observed", 3: "unknown", 4: "suspicious", 5: "outlier"}


def load(path, default=None):
    if default is not None and not os.path.exists(path):
        return default
    try:
        with open(path) as handle:
            return json.load(handle)
    except (OSError, ValueError) as error:
        sys.exit("move_failures: cannot read %s: %s" % (path, error))


Move = collections.namedtuple("Move", "gt_id name class_id radius old new")


def ground_truth_moves(sequence):
    """Every move of the sequence's objects_gt.json whose new place some frame shows."""
    moves = []
    for obj in load(os.path.join(sequence, "objects_gt.json"))["objects"]:
        history = obj["history"]
        for old, new in zip(history, history[1:]):
            if not old["present"] or not new["present"] or new.get("frames_in_view", 1) == 0:
                continue
            moves.append(Move(obj["id"], obj["class"], obj["class_id"], 0.5 * max(obj["size"]),
                              old["centre"], new["centre"]))
    return moves


def near(class_id, centre, move, place):
    return class_id == move.class_id and math.dist(centre, place) < move.radius


def classify(run_dir, sequence, tau_doubt):
    """[(gt id, class, kind, detail)] for the moves of sequence in run_dir."""
    moves = ground_truth_moves(sequence)
    changes = load(os.path.join(run_dir, "changes.json"))["changes"]
    live = load(os.path.join(run_dir, "objects.json"))["objects"]
    nodes = {node["id"]: node
             for node in load(os.path.join(run_dir, "ocg.json"), {"nodes": []})["nodes"]}
    # A removal a `restored` entry undid is no run object of the old place (as ocg_eval).
    restored = {e["object_id"] for e in changes if e["type"] == "restored"}
    gone_from = {}  # gt id -> the `removed` and `moved` entries near its old place
    moved_from = {}  # gt id -> the `moved` ones among them
    for move in moves:
        gone_from[move.gt_id] = [
            e for e in changes
            if (e["type"] == "moved" or (e["type"] == "removed" and e["object_id"] not in restored))
            and near(e["class_id"], e["centroid"], move, move.old)]
        moved_from[move.gt_id] = [e for e in gone_from[move.gt_id] if e["type"] == "moved"]

    rows = []
    for move in moves:
        gone = gone_from[move.gt_id]
        moved = moved_from[move.gt_id]
        right = [e for e in moved if near(move.class_id, e["to"]["cuboid"]["centre"], move, move.new)]
        still = [o for o in live if near(o["class_id"], o["cuboid"]["centre"], move, move.old)]
        if right:
            rows.append((move.gt_id, move.name, "right", "object %d to %d" % (
                right[0]["object_id"], right[0]["to"]["object_id"])))
        elif moved:
            entry = moved[0]
            to_centre = entry["to"]["cuboid"]["centre"]
            detail = "object %d to %d, %.2f from the new place" % (
                entry["object_id"], entry["to"]["object_id"], math.dist(to_centre, move.new))
            for other in moves:
                if other is move or not near(move.class_id, to_centre, other, other.new):
                    continue
                swapped = any(near(move.class_id, e["to"]["cuboid"]["centre"], move, move.new)
                              for e in moved_from[other.gt_id])
                detail += "; %s %d" % ("swapped with" if swapped else "to the new place of",
                                       other.gt_id)
                break
            rows.append((move.gt_id, move.name, "paired wrong", detail))
        elif gone:
            rows.append((move.gt_id, move.name, "removed, unpaired",
                         "object %d" % gone[0]["object_id"]))
        elif still:
            node = nodes.get(still[0]["id"])
            if node is None:
                detail = "object %d, not in the OCG" % still[0]["id"]
            else:
                doubt = node["doubt"]
                detail = "object %d, %s, doubt %.0f %s %g" % (
                    still[0]["id"], STATES.get(node["state"], str(node["state"])), doubt,
                    ">" if doubt > tau_doubt else "<=", tau_doubt)
            rows.append((move.gt_id, move.name, "still mapped", detail))
        else:
            rows.append((move.gt_id, move.name, "never mapped", ""))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pairs", nargs="+", help="RUN_DIR SEQUENCE_DIR, repeated")
    parser.add_argument("--tau-doubt", type=float, default=50.0,
                        help="the runs' OCG.tau_doubt, to compare DoubtValues with (default 50)")
    args = parser.parse_args()
    if len(args.pairs) % 2:
        parser.error("give RUN_DIR SEQUENCE_DIR pairs")
    kinds = collections.Counter()
    for run_dir, sequence in zip(args.pairs[::2], args.pairs[1::2]):
        rows = classify(run_dir, sequence, args.tau_doubt)
        print("%s: %d moves, %d right" % (run_dir, len(rows),
                                          sum(1 for row in rows if row[2] == "right")))
        for gt_id, name, kind, detail in rows:
            print("  %3d %-14s %s%s" % (gt_id, name, kind, ": " + detail if detail else ""))
            kinds[kind] += 1
    print(", ".join("%s %d" % item for item in sorted(kinds.items())))


if __name__ == "__main__":
    main()
