#!/usr/bin/env python3
"""The whole system (SLAM, objects, OCG) fed frame by frame from Python.

Usage: examples/object_slam.py SEQUENCE [--settings S] [--max-frames N] [--out FOLDER]

SEQUENCE is a TUM-format folder: rgb.txt listing "timestamp path" per image and, for the
object map, detections/<timestamp>.txt files (one box a line: class x y w h score, pixels).
`ocg_synth --preset smoke --out SEQUENCE` makes one; its camera.yaml is the default
settings. This is what `ocg_slam run` does, written with your own loader: the script reads
the frames, gives each to ocg.ObjectSlam.track() and prints the poses; at the end the
object map and the changes, and with --out every file `ocg_slam run` writes.

Needs the module on the path: PYTHONPATH=build/python, or an installed OCG-SLAM.
"""
import argparse
import os

import ocg  # first: its ImportError names the interpreter it was built for

import numpy as np


def read_frames(sequence):
    """(timestamp in seconds, image path, (N, 6) detections) for each line of rgb.txt."""
    with open(os.path.join(sequence, "rgb.txt")) as listing:
        for line in listing:
            if line.startswith("#") or not line.strip():
                continue
            stamp, image = line.split()[:2]
            boxes = os.path.join(sequence, "detections", stamp + ".txt")
            detections = np.loadtxt(boxes, ndmin=2) if os.path.exists(boxes) else None
            yield float(stamp), os.path.join(sequence, image), detections


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sequence")
    parser.add_argument("--settings", help="settings file (default: SEQUENCE/camera.yaml)")
    parser.add_argument("--max-frames", type=int, default=0, help="stop after N frames (0: all)")
    parser.add_argument("--out", help="write ocg_slam run's files into this folder")
    args = parser.parse_args()

    slam = ocg.ObjectSlam(args.settings or os.path.join(args.sequence, "camera.yaml"))
    tracked = 0
    for index, (timestamp, image, detections) in enumerate(read_frames(args.sequence)):
        if args.max_frames and index >= args.max_frames:
            break
        # Grey pixels as `ocg_slam run` decodes them (the same files, byte for byte); the file
        # gives the objects' colour signatures at shutdown(). A BGR image would give them too.
        result = slam.track(ocg.read_image(image), timestamp, detections, image_path=image)
        if result.pose is None:
            print("%.6f  not tracked (%s)" % (timestamp, result.state))
            continue
        tracked += 1
        T_cw = result.pose
        camera_centre = -T_cw[:3, :3].T @ T_cw[:3, 3]  # world frame, map units
        boxes = 0 if detections is None else len(detections)
        print("%.6f  camera at %s, %d boxes" % (timestamp, np.round(camera_centre, 3), boxes))
    slam.shutdown()

    objects = slam.objects()
    live = objects["objects"] if objects else []
    print("%d frames tracked, %d keyframes; %d objects" % (
        tracked, len(slam.keyframe_trajectory()), len(live)))
    for change in (slam.changes() or {}).get("changes", []):
        print("change:", change)
    if args.out:
        os.makedirs(args.out, exist_ok=True)
        report = slam.save(args.out)
        print("wrote %s (run.json: %d frames tracked)" % (args.out, report["frames_tracked"]))


if __name__ == "__main__":
    main()
