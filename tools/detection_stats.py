#!/usr/bin/env python3
"""Statistics of a detections folder, to put a detector model beside a real detector.

Usage:
  tools/detection_stats.py [--window 4] [--max-gap 1.0] [--iou 0.3] [--markdown NAME]
                           [--json] FOLDER...

FOLDER is a detections folder of EAO text files (`<timestamp>.txt`, one box a line:
`class x y w h score`), or a sequence folder holding `detections/` (ocg_synth's output,
the TUM folder of ../shared/data). The timestamps in the file names give the clock.

Prints, per folder:
  boxes per frame       mean over all frames;
  window means          boxes per frame averaged over consecutive, non-overlapping windows
                        of --window seconds from the first frame: lowest, highest, and
                        their std / mean (the detector's swings, comparable between scenes);
  scores                mean, std and the share below 0.5, 0.5-0.7, 0.7-0.9, from 0.9;
  miss runs             boxes are chained from frame to frame (greedy, highest IoU first,
                        any class, IoU >= --iou against the chain's last box); a chain
                        that finds its box again after k frames without it had a miss run
                        of k frames (a box present before and after). Chains unseen for
                        more than --max-gap seconds end. Reported: runs per 100 chained
                        frames, the share of runs of 1, 2, 3-5, 6-15 and more frames, the
                        mean run in frames and in seconds;
  class flips           runs of a chain's box in a class other than the chain's most
                        common one: runs per 100 chained frames, mean run in frames.
Needs Python 3 only.
"""
import argparse
import json
import os
import statistics
import sys


def read_folder(folder):
    """Returns [(timestamp, [(class, x, y, w, h, score), ...]), ...] sorted by time."""
    if os.path.isdir(os.path.join(folder, "detections")):
        folder = os.path.join(folder, "detections")
    frames = []
    for name in os.listdir(folder):
        if not name.endswith(".txt"):
            continue
        try:
            stamp = float(name[:-4])
        except ValueError:
            sys.exit("%s: file name '%s' is not a timestamp" % (folder, name))
        boxes = []
        with open(os.path.join(folder, name)) as text:
            for number, line in enumerate(text, 1):
                fields = line.split()
                if not fields or fields[0].startswith("#"):
                    continue
                if len(fields) != 6:
                    sys.exit("%s:%d: expected 'class x y w h score', got '%s'" %
                             (os.path.join(folder, name), number, line.strip()))
                values = [float(v) for v in fields]
                boxes.append((int(values[0]),) + tuple(values[1:]))
        frames.append((stamp, boxes))
    if not frames:
        sys.exit("%s: no detection files (<timestamp>.txt)" % folder)
    frames.sort()
    return frames


def iou(a, b):
    ax2, ay2 = a[1] + a[3], a[2] + a[4]
    bx2, by2 = b[1] + b[3], b[2] + b[4]
    w = min(ax2, bx2) - max(a[1], b[1])
    h = min(ay2, by2) - max(a[2], b[2])
    if w <= 0 or h <= 0:
        return 0.0
    inter = w * h
    return inter / (a[3] * a[4] + b[3] * b[4] - inter)


def chains(frames, max_gap_frames, min_iou):
    """Chains boxes over frames; returns (miss runs in frames, chains' class lists)."""
    live = []  # [last box, last frame index, classes]
    done = []
    runs = []
    for index, (_, boxes) in enumerate(frames):
        still = []
        for chain in live:
            if index - chain[1] - 1 > max_gap_frames:
                done.append(chain)
            else:
                still.append(chain)
        live = still
        pairs = sorted(((iou(chain[0], box), c, b) for c, chain in enumerate(live)
                        for b, box in enumerate(boxes)), reverse=True)
        used_chain, used_box = set(), set()
        for overlap, c, b in pairs:
            if overlap < min_iou:
                break
            if c in used_chain or b in used_box:
                continue
            used_chain.add(c)
            used_box.add(b)
            gap = index - live[c][1] - 1
            if gap > 0:
                runs.append(gap)
            live[c][0] = boxes[b]
            live[c][1] = index
            live[c][2].append(boxes[b][0])
        for b, box in enumerate(boxes):
            if b not in used_box:
                live.append([box, index, [box[0]]])
    return runs, [chain[2] for chain in done + live]


def flip_runs(classes):
    """Runs of a class other than the most common one in a chain's class list."""
    common = max(set(classes), key=classes.count)
    runs, length = [], 0
    for c in classes:
        if c != common:
            length += 1
        elif length:
            runs.append(length)
            length = 0
    if length:
        runs.append(length)
    return runs


def measure(folder, window, max_gap, min_iou):
    frames = read_folder(folder)
    counts = [len(boxes) for _, boxes in frames]
    span = frames[-1][0] - frames[0][0]
    period = span / max(len(frames) - 1, 1)
    means = []
    start, bucket = frames[0][0], []
    for stamp, boxes in frames:
        if stamp - start >= window:
            means.append(sum(bucket) / len(bucket))
            start, bucket = stamp, []
        bucket.append(len(boxes))
    if bucket and (frames[-1][0] - start) >= 0.75 * window:  # a last, nearly full window
        means.append(sum(bucket) / len(bucket))
    scores = [box[5] for _, boxes in frames for box in boxes]
    runs, class_lists = chains(frames, max(1, round(max_gap / period)), min_iou)
    chained = sum(len(c) for c in class_lists)
    flips = [r for c in class_lists if len(c) >= 3 for r in flip_runs(c)]

    def share(values, low, high):
        return sum(1 for v in values if low <= v < high) / max(len(values), 1)

    return {
        "folder": folder,
        "frames": len(frames),
        "seconds": span,
        "boxes_per_frame": statistics.mean(counts),
        "window_seconds": window,
        "window_min": min(means) if means else float("nan"),
        "window_max": max(means) if means else float("nan"),
        # Spread of the window means relative to their mean: comparable between scenes
        # with different numbers of objects.
        "window_cv": (statistics.pstdev(means) / statistics.mean(means)
                      if len(means) > 1 and statistics.mean(means) > 0 else float("nan")),
        "score_mean": statistics.mean(scores) if scores else float("nan"),
        "score_std": statistics.pstdev(scores) if scores else float("nan"),
        "score_below_0.5": share(scores, 0.0, 0.5),
        "score_0.5_0.7": share(scores, 0.5, 0.7),
        "score_0.7_0.9": share(scores, 0.7, 0.9),
        "score_from_0.9": share(scores, 0.9, 2.0),
        "miss_runs_per_100": 100.0 * len(runs) / max(chained, 1),
        "miss_run_1": share(runs, 1, 2),
        "miss_run_2": share(runs, 2, 3),
        "miss_run_3_5": share(runs, 3, 6),
        "miss_run_6_15": share(runs, 6, 16),
        "miss_run_over_15": share(runs, 16, 1e9),
        "miss_run_mean_frames": statistics.mean(runs) if runs else 0.0,
        "miss_run_mean_seconds": period * statistics.mean(runs) if runs else 0.0,
        "flip_runs_per_100": 100.0 * len(flips) / max(chained, 1),
        "flip_run_mean_frames": statistics.mean(flips) if flips else 0.0,
    }


def print_text(s):
    print("%s: %d frames over %.1f s" % (s["folder"], s["frames"], s["seconds"]))
    print("  boxes per frame %.2f; %g-second means from %.2f to %.2f (lowest / mean %.2f, "
          "std / mean %.2f)" % (s["boxes_per_frame"], s["window_seconds"], s["window_min"],
                                s["window_max"], s["window_min"] / s["boxes_per_frame"],
                                s["window_cv"]))
    print("  scores mean %.3f std %.3f; < 0.5 %.0f %%, 0.5-0.7 %.0f %%, 0.7-0.9 %.0f %%, "
          ">= 0.9 %.0f %%" % (s["score_mean"], s["score_std"], 100 * s["score_below_0.5"],
                              100 * s["score_0.5_0.7"], 100 * s["score_0.7_0.9"],
                              100 * s["score_from_0.9"]))
    print("  miss runs %.2f per 100 chained frames; 1: %.0f %%, 2: %.0f %%, 3-5: %.0f %%, "
          "6-15: %.0f %%, > 15: %.0f %%; mean %.2f frames (%.3f s)" %
          (s["miss_runs_per_100"], 100 * s["miss_run_1"], 100 * s["miss_run_2"],
           100 * s["miss_run_3_5"], 100 * s["miss_run_6_15"], 100 * s["miss_run_over_15"],
           s["miss_run_mean_frames"], s["miss_run_mean_seconds"]))
    print("  class flips %.2f runs per 100 chained frames, mean %.2f frames" %
          (s["flip_runs_per_100"], s["flip_run_mean_frames"]))


MARKDOWN_HEADER = (
    "| detections | frames | boxes/frame | 4-s means min–max | lowest 4-s / mean | 4-s std/mean | mean score | score std | < 0.5 "
    "| ≥ 0.9 | miss runs /100 | runs 1 / 2 / 3–5 / 6–15 / >15 frames | mean run | "
    "flip runs /100 | mean flip |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")


def markdown_row(name, s):
    return ("| %s | %d | %.2f | %.1f–%.1f | %.2f | %.2f | %.3f | %.3f | %.0f %% | %.0f %% | %.2f | "
            "%.0f / %.0f / %.0f / %.0f / %.0f %% | %.2f fr (%.2f s) | %.2f | %.1f fr |" %
            (name, s["frames"], s["boxes_per_frame"], s["window_min"], s["window_max"],
             s["window_min"] / s["boxes_per_frame"], s["window_cv"], s["score_mean"], s["score_std"], 100 * s["score_below_0.5"],
             100 * s["score_from_0.9"], s["miss_runs_per_100"], 100 * s["miss_run_1"],
             100 * s["miss_run_2"], 100 * s["miss_run_3_5"], 100 * s["miss_run_6_15"],
             100 * s["miss_run_over_15"], s["miss_run_mean_frames"],
             s["miss_run_mean_seconds"], s["flip_runs_per_100"], s["flip_run_mean_frames"]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folders", nargs="+", metavar="FOLDER")
    parser.add_argument("--window", type=float, default=4.0, help="seconds (default 4)")
    parser.add_argument("--max-gap", type=float, default=1.0,
                        help="seconds a chain may go unseen (default 1)")
    parser.add_argument("--iou", type=float, default=0.3, help="chaining IoU (default 0.3)")
    parser.add_argument("--markdown", action="store_true",
                        help="one Markdown table row per folder (named by the folder)")
    parser.add_argument("--json", action="store_true", help="one JSON object per folder")
    args = parser.parse_args()
    if args.markdown:
        print(MARKDOWN_HEADER)
    for folder in args.folders:
        if not os.path.isdir(folder):
            sys.exit("%s: not a folder" % folder)
        s = measure(folder, args.window, args.max_gap, args.iou)
        if args.json:
            print(json.dumps(s))
        elif args.markdown:
            print(markdown_row(os.path.basename(os.path.normpath(folder)), s))
        else:
            print_text(s)


if __name__ == "__main__":
    main()
