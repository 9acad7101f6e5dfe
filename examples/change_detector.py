#!/usr/bin/env python3
"""The OCG change detector driven from Python, as any SLAM system would drive it.

Usage: examples/change_detector.py [OBSERVATIONS.jsonl] [--mode M]
       (default: tests/data/ocg_example.jsonl, the paper's moved-cup story)

Each line of the stream is one keyframe of some SLAM system (the replay format of
docs/ocg.md): its world-to-camera pose, its camera, the ids of the map objects it matched
to a detection, and the centroids that are new. The script feeds them to
ocg.ChangeDetector one by one and prints every object's state, DoubtValue and
ActiveEdgeRate after each keyframe, and the objects removed as changed.

Needs the module on the path: PYTHONPATH=build/python, or an installed OCG-SLAM.
"""
import argparse
import json
import os

import ocg  # first: its ImportError names the interpreter it was built for

import numpy as np

STATE_NAMES = {1: "observed", 2: "recent", 3: "unknown", 4: "suspicious"}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("observations", nargs="?",
                        default=os.path.join(here, "..", "tests", "data", "ocg_example.jsonl"))
    parser.add_argument("--mode", default="paper", help="OCG.mode: paper, improved, ...")
    args = parser.parse_args()

    detector = ocg.ChangeDetector(ocg.OcgOptions(mode=args.mode))
    with open(args.observations) as stream:
        for line in stream:
            if not line.strip():
                continue
            keyframe = json.loads(line)
            # Your SLAM system provides these at each keyframe.
            T_cw = np.array(keyframe["T_cw"], dtype=float).reshape(4, 4)
            camera = ocg.PinholeCamera(**keyframe["camera"])
            centroids = {int(i): c for i, c in keyframe.get("centroids", {}).items()}
            classes = {int(i): c for i, c in keyframe.get("classes", {}).items()}
            states = detector.process(keyframe["keyframe"], T_cw, camera, keyframe["observed"],
                                      centroids, timestamp=keyframe["timestamp"], classes=classes)
            summary = ", ".join("%d: %s doubt %g rate %.2f" % (
                s.id, STATE_NAMES[s.state], s.doubt, s.active_edge_rate) for s in states.objects)
            print("keyframe %d | %s" % (states.keyframe, summary))
            for event in states.removed:
                print("  removed object %d (class %d, doubt %g) at %s" % (
                    event.object_id, event.class_id, event.doubt,
                    np.round(event.centroid, 3).tolist() if event.centroid is not None else "?"))
    print("%d objects left in the map" % len(detector))


if __name__ == "__main__":
    main()
