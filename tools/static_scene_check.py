#!/usr/bin/env python3
"""Change detection on a static scene: every removal is a false change report.

Usage:
  tools/static_scene_check.py [--min-observations N] [--reach F] [--scene-counts FILE]
                              [--tolerance T] [--json] RUN_DIR...

RUN_DIR is the output folder of `ocg_slam objects` or `ocg_slam run --detections`
(objects.json, changes.json and ocg_observations.jsonl inside). Nothing moves in a static
scene, so every object the change detection removes was removed wrongly. Counts:
  removals             change-log entries of type "removed" (the OCG's removals; merges
                       and drops of duplicates are hygiene and not counted);
  well observed        removals of objects detected in at least N frames (default 30):
                       real objects, not spurious ones;
  false (re-created)   removals followed by a new object of the same class whose centre
                       lies within the removed object's reach: its cuboid's largest side
                       times F (default 1.0) from its centre. The object was still there;
  restored             removals undone later (change-log type "restored": the object was
                       found again at its place and is live with its id); a restored
                       removal is not counted as false;
  standing             removals not restored: the objects the run lost.
With --scene-counts (a JSON object: class name -> count of that class in the scene) the
live objects at the end are compared per class: within T (default 0.25) of the count.
Prints one block per run (or one JSON object per run with --json). Exits 1 when a file
is missing or malformed (naming it), 0 otherwise. Needs Python 3 only.
"""
import argparse
import json
import math
import os
import sys


class CheckError(Exception):
    pass


def load_json(path):
    try:
        with open(path) as handle:
            return json.load(handle)
    except OSError as error:
        raise CheckError("%s: cannot read (%s)" % (path, error.strerror))
    except ValueError as error:
        raise CheckError("%s: not valid JSON (%s)" % (path, error))


def first_keyframes(path):
    """Object id -> the first keyframe that observed it, from ocg_observations.jsonl."""
    first = {}
    try:
        with open(path) as handle:
            for number, line in enumerate(handle, 1):
                if not line.strip():
                    continue
                try:
                    entry = json.loads(line)
                    keyframe = entry["keyframe"]
                    for object_id in entry["observed"]:
                        first.setdefault(object_id, keyframe)
                except (ValueError, KeyError, TypeError) as error:
                    raise CheckError("%s:%d: not an OCG observation line (%s)" % (path, number, error))
    except OSError as error:
        raise CheckError("%s: cannot read (%s)" % (path, error.strerror))
    return first


def field(entry, key, path):
    if key not in entry:
        raise CheckError("%s: an entry has no \"%s\": %s" % (path, key, json.dumps(entry)[:120]))
    return entry[key]


def check_run(folder, min_observations, reach_factor, scene_counts, tolerance):
    objects_path = os.path.join(folder, "objects.json")
    changes_path = os.path.join(folder, "changes.json")
    observations_path = os.path.join(folder, "ocg_observations.jsonl")
    objects = field(load_json(objects_path), "objects", objects_path)
    changes = field(load_json(changes_path), "changes", changes_path)
    first = first_keyframes(observations_path)

    # Every object that ever existed: class and last centre (live ones from objects.json,
    # the others from their last change-log entry).
    known = {}
    for entry in changes:
        known[field(entry, "object_id", changes_path)] = (
            field(entry, "class", changes_path), field(entry, "centroid", changes_path))
    for entry in objects:
        known[field(entry, "id", objects_path)] = (
            field(entry, "class", objects_path), field(entry, "cuboid", objects_path)["centre"])

    removals = []
    for index, entry in enumerate(changes):
        if field(entry, "type", changes_path) not in ("removed", "moved"):  # a move removes too
            continue
        # Undone when a later "restored" entry names the object (before it is removed again).
        restored = False
        for later in changes[index + 1:]:
            if later.get("object_id") != entry["object_id"]:
                continue
            if later.get("type") in ("removed", "moved"):
                break
            if later.get("type") == "restored":
                restored = True
                break
        object_id = entry["object_id"]
        centre = field(entry, "centroid", changes_path)
        reach = reach_factor * max(field(entry, "cuboid", changes_path)["size"])
        keyframe = field(entry, "keyframe", changes_path)
        recreated = sorted(
            other for other, (name, other_centre) in known.items()
            if other != object_id and name == entry["class"] and first.get(other, -1) > keyframe
            and math.dist(centre, other_centre) <= reach)
        removals.append({
            "object_id": object_id,
            "class": entry["class"],
            "keyframe": keyframe,
            "timestamp": entry.get("timestamp"),
            "observations": field(entry, "observations", changes_path),
            "recreated_as": recreated,
            "restored": restored,
        })

    live = {}
    for entry in objects:
        live[entry["class"]] = live.get(entry["class"], 0) + 1
    report = {
        "run": folder,
        "removals": len(removals),
        "well_observed_removals": sum(r["observations"] >= min_observations for r in removals),
        "false_removals": sum(bool(r["recreated_as"]) and not r["restored"] for r in removals),
        "restored": sum(r["restored"] for r in removals),
        "standing_removals": sum(not r["restored"] for r in removals),
        "min_observations": min_observations,
        "live_objects": len(objects),
        "live_per_class": dict(sorted(live.items())),
        "removed": removals,
    }
    if scene_counts is not None:
        classes = {}
        for name, count in sorted(scene_counts.items()):
            have = live.get(name, 0)
            classes[name] = {"scene": count, "live": have,
                             "within": abs(have - count) <= tolerance * count}
        report["per_class"] = classes
        report["classes_within"] = sum(c["within"] for c in classes.values())
    return report


def print_report(report):
    print("%s" % report["run"])
    print("  removals by change detection: %d" % report["removals"])
    print("  of objects observed >= %d times: %d" % (report["min_observations"],
                                                     report["well_observed_removals"]))
    print("  false (re-created at its place): %d" % report["false_removals"])
    print("  restored later: %d" % report["restored"])
    print("  standing (not restored): %d" % report["standing_removals"])
    for r in report["removed"]:
        notes = []
        if r["recreated_as"]:
            notes.append("re-created as %s" % ", ".join(str(i) for i in r["recreated_as"]))
        if r["restored"]:
            notes.append("restored")
        print("    keyframe %4d  id %4d  %-14s observed %4d%s" % (
            r["keyframe"], r["object_id"], r["class"], r["observations"],
            ("  (" + "; ".join(notes) + ")") if notes else ""))
    print("  live objects: %d  %s" % (report["live_objects"], ", ".join(
        "%s %d" % item for item in report["live_per_class"].items())))
    if "per_class" in report:
        print("  per class against the scene (%d of %d within tolerance):" % (
            report["classes_within"], len(report["per_class"])))
        for name, c in report["per_class"].items():
            print("    %-14s scene %3d  live %3d  %s" % (name, c["scene"], c["live"],
                                                       "ok" if c["within"] else "OFF"))


def main():
    parser = argparse.ArgumentParser(
        description=__doc__.splitlines()[0], epilog="\n".join(__doc__.splitlines()[2:]),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", metavar="RUN_DIR", help="output folders of ocg_slam")
    parser.add_argument("--min-observations", type=int, default=30,
                        help="frames an object was detected in to count as well observed (30)")
    parser.add_argument("--reach", type=float, default=1.0,
                        help="a new object within this many largest sides of a removed one's "
                             "centre re-creates it (1.0)")
    parser.add_argument("--scene-counts", help="JSON file: class name -> count in the scene")
    parser.add_argument("--tolerance", type=float, default=0.25,
                        help="allowed relative difference of live objects per class (0.25)")
    parser.add_argument("--json", action="store_true", help="one JSON object per run")
    args = parser.parse_args()
    if args.min_observations < 1:
        parser.error("--min-observations must be at least 1")
    if args.reach <= 0 or args.tolerance < 0:
        parser.error("--reach must be positive and --tolerance non-negative")
    try:
        scene_counts = None
        if args.scene_counts:
            scene_counts = load_json(args.scene_counts)
            if not isinstance(scene_counts, dict) or not all(
                    isinstance(v, int) and v > 0 for v in scene_counts.values()):
                raise CheckError("%s: must be a JSON object of class name -> positive count"
                                 % args.scene_counts)
        for folder in args.runs:
            if not os.path.isdir(folder):
                raise CheckError("%s: not a folder (give the --out folder of an ocg_slam run)"
                                 % folder)
            report = check_run(folder, args.min_observations, args.reach, scene_counts,
                               args.tolerance)
            if args.json:
                print(json.dumps(report))
            else:
                print_report(report)
    except CheckError as error:
        sys.exit("static_scene_check: %s" % error)


if __name__ == "__main__":
    main()
