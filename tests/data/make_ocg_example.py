#!/usr/bin/env python3
"""Writes ocg_example.jsonl: the paper's Fig. 4/5 story as an ocg_replay input.

Objects 1-4 (cup, bottle, keyboard, mouse) stand on a table at the origin; 5-6 (book,
tv) on a shelf ten metres away. The camera looks at the table (keyframes 0-2), turns to
the shelf (3-4); meanwhile the cup (1) is moved away. Back at the table (5-6) the cup's
neighbours are seen but the cup is not: it becomes suspicious, and when the camera turns
to the shelf again (7) it is removed. At keyframe 8 the cup is detected at its new place
as a new object (7). Rerun this script to regenerate the file; it needs only Python 3.
"""
import json
import math
import os


def look_at(eye, target):
    """Row-major 4x4 world-to-camera matrix, world up +z, image y down."""
    z = [t - e for t, e in zip(target, eye)]
    n = math.sqrt(sum(v * v for v in z))
    z = [v / n for v in z]
    x = [z[1], -z[0], 0.0]  # z cross (0, 0, 1)
    n = math.sqrt(sum(v * v for v in x))
    x = [v / n for v in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    rows = [x, y, z]  # R_cw rows are the camera axes in the world
    t = [-sum(r[i] * eye[i] for i in range(3)) for r in rows]
    return [v for r, ti in zip(rows, t) for v in (r + [ti])] + [0.0, 0.0, 0.0, 1.0]


PLACES = {1: [0.0, 0.0, 0.05], 2: [0.3, 0.2, 0.1], 3: [-0.3, 0.2, 0.02], 4: [0.0, -0.3, 0.02],
          5: [10.0, 0.0, 0.1], 6: [10.0, 0.4, 0.3], 7: [0.6, -0.5, 0.05]}
CLASSES = {1: 41, 2: 39, 3: 66, 4: 64, 5: 73, 6: 62, 7: 41}
TABLE = look_at([-2.0, 0.0, 0.8], [0.0, 0.0, 0.0])
SHELF = look_at([8.0, 0.0, 0.8], [10.0, 0.0, 0.0])
CAMERA = {"fx": 517.3, "fy": 516.5, "cx": 318.6, "cy": 255.3, "width": 640, "height": 480}
SCRIPT = [(TABLE, [1, 2, 3, 4])] * 3 + [(SHELF, [5, 6])] * 2 + [(TABLE, [2, 3, 4])] * 2 + \
         [(SHELF, [5, 6]), (TABLE, [2, 3, 4, 7])]

announced = set()
lines = []
for keyframe, (pose, observed) in enumerate(SCRIPT):
    new = [i for i in observed if i not in announced]
    announced.update(new)
    lines.append(json.dumps({
        "keyframe": keyframe, "timestamp": round(0.5 * keyframe, 3), "T_cw": [round(v, 9) for v in pose],
        "camera": CAMERA, "observed": observed,
        "centroids": {str(i): PLACES[i] for i in new}, "classes": {str(i): CLASSES[i] for i in new}}))
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "ocg_example.jsonl"), "w") as out:
    out.write("\n".join(lines) + "\n")
