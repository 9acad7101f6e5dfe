#!/usr/bin/env python3
"""The static objects Table I finds unidentified in runs on generated sequences, and why.

Usage:
  tools/unmapped_objects.py [--build build] [--min-boxes 8] RUN_DIR SEQUENCE_DIR [RUN_DIR SEQUENCE_DIR ...]

For each pair (a run folder of `ocg_slam objects` or `ocg_slam run` on ground-truth poses,
and the `ocg_synth` folder it ran on), scores the run with `ocg_eval objects --json` and,
for every static object it lists as unidentified, counts the detector's boxes on it: the
boxes of its class at or above Objects.min_confidence (0.4) whose IoU with the object's
projected cuboid (ground-truth pose, the sequence's camera with its distortion) exceeds
0.3, and of those the ones within 4 pixels of the image edge (truncated: they feed no
triangulation). Each object gets one kind:
  few boxes    fewer than --min-boxes untruncated boxes (Objects.candidate_min_observations):
               never triangulated, by design;
  misplaced    a redundant object (spurious or duplicate) of its class within 1 m: it was
               mapped, away from its place;
  never mapped enough boxes, and no object of its class near it.
Prints one line per object and the count of each kind. Needs Python 3 only.
"""
import argparse
import collections
import json
import math
import os
import subprocess
import sys


def read_camera(path):
    camera = {"k1": 0.0, "k2": 0.0, "k3": 0.0, "p1": 0.0, "p2": 0.0}
    for line in open(path):
        line = line.split("#")[0].strip()
        if ":" not in line:
            continue
        key, value = (part.strip() for part in line.split(":", 1))
        try:
            camera[key.split(".")[-1]] = float(value)
        except ValueError:
            pass
    return camera


def read_poses(path):
    """TUM ground truth: (timestamp, R_wc rows, centre) per line, in file order."""
    poses = []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        t, x, y, z, qx, qy, qz, qw = map(float, line.split()[:8])
        rotation = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
                    [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
                    [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]
        poses.append((t, rotation, (x, y, z)))
    return poses


def project(camera, pose, point):
    """Pixel of a world point (with the camera's distortion), or None behind the camera."""
    _, rotation, centre = pose
    d = [point[i] - centre[i] for i in range(3)]
    p = [sum(rotation[r][c] * d[r] for r in range(3)) for c in range(3)]  # R_wc^T (X - C)
    if p[2] <= 0.05:
        return None
    x, y = p[0] / p[2], p[1] / p[2]
    r2 = x * x + y * y
    radial = 1 + camera["k1"] * r2 + camera["k2"] * r2 * r2 + camera["k3"] * r2 ** 3
    xd = x * radial + 2 * camera["p1"] * x * y + camera["p2"] * (r2 + 2 * x * x)
    yd = y * radial + camera["p1"] * (r2 + 2 * y * y) + 2 * camera["p2"] * x * y
    return camera["fx"] * xd + camera["cx"], camera["fy"] * yd + camera["cy"]


def projected_box(camera, pose, obj):
    state = obj["history"][0]
    cx, cy, cz = state["centre"]
    yaw = state["yaw"]
    sx, sy, sz = obj["size"]
    xs, ys = [], []
    for a in (-0.5, 0.5):
        for b in (-0.5, 0.5):
            for c in (-0.5, 0.5):
                corner = (cx + math.cos(yaw) * a * sx - math.sin(yaw) * b * sy,
                          cy + math.sin(yaw) * a * sx + math.cos(yaw) * b * sy, cz + c * sz)
                pixel = project(camera, pose, corner)
                if pixel is None:
                    return None
                xs.append(pixel[0])
                ys.append(pixel[1])
    return min(xs), min(ys), max(xs), max(ys)


def iou(a, b):
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    if w <= 0 or h <= 0:
        return 0.0
    inter = w * h
    return inter / ((a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter)


def unmapped(build, run_dir, sequence, min_boxes):
    result = subprocess.run([os.path.join(build, "tools", "ocg_eval"), "objects", "--gt",
                             os.path.join(sequence, "objects_gt.json"), "--run", run_dir, "--json"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        sys.exit("ocg_eval objects failed on %s: %s" % (run_dir, result.stderr.strip()))
    metrics = json.loads(result.stdout)
    truth = {o["id"]: o for o in json.load(open(os.path.join(sequence, "objects_gt.json")))["objects"]}
    camera = read_camera(os.path.join(sequence, "camera.yaml"))
    poses = read_poses(os.path.join(sequence, "groundtruth.txt"))
    folder = os.path.join(sequence, "detections")
    files = sorted(os.listdir(folder), key=lambda name: float(os.path.splitext(name)[0]))
    if len(files) != len(poses):
        sys.exit("%s: %d detection files but %d poses" % (sequence, len(files), len(poses)))
    objects = json.load(open(os.path.join(run_dir, "objects.json")))["objects"]
    redundant = set(metrics["spurious_ids"]) | set(metrics["duplicate_ids"])
    rows = []
    for gt_id in metrics["unidentified_static_ids"]:
        obj = truth[gt_id]
        boxes = truncated = 0
        frames = []
        for index, name in enumerate(files):
            projected = projected_box(camera, poses[index], obj)
            if projected is None:
                continue
            for line in open(os.path.join(folder, name)):
                fields = line.split()
                if len(fields) < 6 or int(fields[0]) != obj["class_id"] or float(fields[5]) < 0.4:
                    continue
                x, y, w, h = map(float, fields[1:5])
                if iou((x, y, x + w, y + h), projected) <= 0.3:
                    continue
                boxes += 1
                frames.append(poses[index][0])
                truncated += (x <= 4 or y <= 4 or x + w >= camera["width"] - 4 or
                              y + h >= camera["height"] - 4)
        centre = obj["history"][0]["centre"]
        near = [o["id"] for o in objects if o["class_id"] == obj["class_id"] and
                o["id"] in redundant and math.dist(o["cuboid"]["centre"], centre) < 1.0]
        if near:
            kind = "misplaced"
        elif boxes - truncated < min_boxes:
            kind = "few boxes"
        else:
            kind = "never mapped"
        span = frames[-1] - frames[0] if frames else 0.0
        rows.append((gt_id, obj["class"], boxes, truncated, span, kind, near))
    return metrics, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pairs", nargs="+", help="RUN_DIR SEQUENCE_DIR, repeated")
    parser.add_argument("--build", default="build", help="build folder (default: build)")
    parser.add_argument("--min-boxes", type=int, default=8,
                        help="untruncated boxes a candidate needs (Objects.candidate_min_observations)")
    args = parser.parse_args()
    if len(args.pairs) % 2:
        parser.error("give RUN_DIR SEQUENCE_DIR pairs")
    kinds = collections.Counter()
    for run_dir, sequence in zip(args.pairs[::2], args.pairs[1::2]):
        metrics, rows = unmapped(args.build, run_dir, sequence, args.min_boxes)
        print("%s: Acc %.3f, %d unidentified static" % (run_dir, metrics["acc"], len(rows)))
        for gt_id, name, boxes, truncated, span, kind, near in rows:
            print("  %3d %-14s %4d boxes (%d truncated) over %5.1f s: %s%s" % (
                gt_id, name, boxes, truncated, span, kind,
                " (objects %s)" % ", ".join(map(str, near)) if near else ""))
            kinds[kind] += 1
    print(", ".join("%s %d" % item for item in sorted(kinds.items())))


if __name__ == "__main__":
    main()
