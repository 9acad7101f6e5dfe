#!/usr/bin/python3
"""Detection files against reference detection files (both EAO text: one <timestamp>.txt
per image, "class_id x y w h confidence", x y the top-left corner).

A reference box is matched by a detected box of the same class with IoU >= --iou (0.5),
one to one, detected boxes taken in decreasing confidence, each to the unmatched
reference box it overlaps most. Prints the matched share of the reference boxes, the
detected boxes left unmatched per frame, and both per class; --json for a machine-readable
summary. With --count-class C and no reference: frames with a box of class C and boxes.

usage: detector_eval.py --frames rgb.txt --detections DIR [--reference DIR] [--iou 0.5]
                        [--min-score S] [--count-class 2] [--json] [--brief]
"""

import argparse
import collections
import json
import os
import sys

COCO = ("person bicycle car motorcycle airplane bus train truck boat traffic_light "
        "fire_hydrant stop_sign parking_meter bench bird cat dog horse sheep cow elephant "
        "bear zebra giraffe backpack umbrella handbag tie suitcase frisbee skis snowboard "
        "sports_ball kite baseball_bat baseball_glove skateboard surfboard tennis_racket "
        "bottle wine_glass cup fork knife spoon bowl banana apple sandwich orange broccoli "
        "carrot hot_dog pizza donut cake chair couch potted_plant bed dining_table toilet tv "
        "laptop mouse remote keyboard cell_phone microwave oven toaster sink refrigerator "
        "book clock vase scissors teddy_bear hair_drier toothbrush").split()


def read_frames(path):
    frames = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                frames.append(line.split()[0])
    return frames


def read_boxes(folder, stamp, min_score=0.0):
    path = os.path.join(folder, stamp + ".txt")
    if not os.path.exists(path):
        return []
    boxes = []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if len(fields) == 6 and float(fields[5]) >= min_score:
                boxes.append((int(fields[0]), *map(float, fields[1:])))
    return boxes


def iou(a, b):
    w = min(a[1] + a[3], b[1] + b[3]) - max(a[1], b[1])
    h = min(a[2] + a[4], b[2] + b[4]) - max(a[2], b[2])
    if w <= 0 or h <= 0:
        return 0.0
    inter = w * h
    return inter / (a[3] * a[4] + b[3] * b[4] - inter)


def match(detected, reference, threshold):
    """Number of matched pairs per class, one to one."""
    used = set()
    matched = collections.Counter()
    for d in sorted(detected, key=lambda box: -box[5]):
        best, best_iou = None, threshold
        for k, r in enumerate(reference):
            if k in used or r[0] != d[0]:
                continue
            value = iou(d, r)
            if value >= best_iou:
                best, best_iou = k, value
        if best is not None:
            used.add(best)
            matched[d[0]] += 1
    return matched


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", required=True, help="rgb.txt listing the frames")
    parser.add_argument("--detections", required=True, help="folder of detection files")
    parser.add_argument("--reference", help="folder of reference detection files")
    parser.add_argument("--iou", type=float, default=0.5)
    parser.add_argument("--min-score", type=float, default=0.0,
                        help="ignore detected boxes below this confidence")
    parser.add_argument("--count-class", type=int, help="without a reference: count this class")
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--brief", action="store_true", help="the summary line alone")
    args = parser.parse_args()
    frames = read_frames(args.frames)
    if not frames:
        sys.exit(f"detector_eval: {args.frames} lists no frame")

    if args.reference is None:
        if args.count_class is None:
            sys.exit("detector_eval: give --reference DIR or --count-class C")
        with_class, boxes = 0, 0
        for stamp in frames:
            n = sum(1 for b in read_boxes(args.detections, stamp, args.min_score)
                    if b[0] == args.count_class)
            with_class += n > 0
            boxes += n
        result = {"frames": len(frames), "frames_with_class": with_class, "boxes": boxes,
                  "class": COCO[args.count_class]}
        if args.json:
            print(json.dumps(result))
        else:
            print(f"{COCO[args.count_class]}: {boxes} boxes, in {with_class} of {len(frames)} "
                  f"frames ({boxes / len(frames):.2f} per frame)")
        return

    refs, dets, matched = collections.Counter(), collections.Counter(), collections.Counter()
    for stamp in frames:
        detected = read_boxes(args.detections, stamp, args.min_score)
        reference = read_boxes(args.reference, stamp)
        refs.update(b[0] for b in reference)
        dets.update(b[0] for b in detected)
        matched.update(match(detected, reference, args.iou))
    total_ref, total_det, total_matched = sum(refs.values()), sum(dets.values()), sum(matched.values())
    result = {
        "frames": len(frames), "reference_boxes": total_ref, "detected_boxes": total_det,
        "matched": total_matched,
        "matched_share": total_matched / total_ref if total_ref else 0.0,
        "unmatched_detected_per_frame": (total_det - total_matched) / len(frames),
        "per_class": {COCO[c]: {"reference": refs[c], "detected": dets[c], "matched": matched[c]}
                      for c in sorted(set(refs) | set(dets))},
    }
    if args.json:
        print(json.dumps(result, indent=1))
        return
    print(f"{len(frames)} frames: {total_matched} of {total_ref} reference boxes matched "
          f"({100 * result['matched_share']:.0f} %) at IoU >= {args.iou}, same class; "
          f"{total_det} detected, {total_det - total_matched} unmatched "
          f"({result['unmatched_detected_per_frame']:.2f} per frame)")
    if args.brief:
        return
    print(f"{'class':<14} {'reference':>9} {'matched':>8} {'detected':>9} {'unmatched':>10}")
    for name, row in result["per_class"].items():
        print(f"{name:<14} {row['reference']:>9} {row['matched']:>8} {row['detected']:>9} "
              f"{row['detected'] - row['matched']:>10}")


if __name__ == "__main__":
    main()
