#!/usr/bin/env python3
"""Builds the soak's long sequence (tools/soak.sh): a TUM sequence played forward and back,
pass after pass, every frame with a fresh timestamp at the sequence's own frame rate.

Usage: soak_sequence.py SOURCE OUT MINUTES [MAX_FPS]
SOURCE: a TUM folder (rgb.txt, rgb/, detections/). OUT gets rgb.txt, rgb (a link to
SOURCE's) and detections/ (one link per frame to SOURCE's file of that image). Enough
passes (forward and back) for MINUTES at up to MAX_FPS (default 50) frames a second, at
least 2. Prints the number of passes.
"""
import math
import os
import shutil
import sys


def read_frames(rgb_txt):
    frames = []
    with open(rgb_txt) as listing:
        for line in listing:
            if line.strip() and not line.startswith("#"):
                stamp, image = line.split()[:2]
                frames.append((stamp, image))
    return frames


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    source, out, minutes = os.path.abspath(sys.argv[1]), sys.argv[2], float(sys.argv[3])
    max_fps = float(sys.argv[4]) if len(sys.argv) == 5 else 50.0
    if not max_fps > 0:
        sys.exit("soak_sequence.py: MAX_FPS must be positive, got %s" % sys.argv[4])
    frames = read_frames(os.path.join(source, "rgb.txt"))
    if len(frames) < 3:
        sys.exit("soak_sequence.py: %s lists fewer than 3 frames" % source)
    stamps = [float(stamp) for stamp, _ in frames]
    step = sorted(b - a for a, b in zip(stamps, stamps[1:]))[len(stamps) // 2]
    one_pass = frames + frames[-2:0:-1]  # forward, then back without repeating the ends
    passes = max(2, math.ceil(minutes * 60 * max_fps / len(one_pass)))
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(out, "detections"))
    os.symlink(os.path.join(source, "rgb"), os.path.join(out, "rgb"))
    detections = os.path.join(source, "detections")
    lines = ["# soak: %s forward and back, %d passes\n" % (source, passes)]
    for index in range(passes * len(one_pass)):
        old_stamp, image = one_pass[index % len(one_pass)]
        stamp = "%.6f" % (stamps[0] + index * step)
        lines.append("%s %s\n" % (stamp, image))
        detection = os.path.join(detections, old_stamp + ".txt")
        if os.path.exists(detection):
            os.symlink(detection, os.path.join(out, "detections", stamp + ".txt"))
    with open(os.path.join(out, "rgb.txt"), "w") as listing:
        listing.writelines(lines)
    print(passes)


if __name__ == "__main__":
    main()
