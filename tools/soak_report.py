#!/usr/bin/env python3
"""The soak's results (tools/soak.sh) from the progress lines `ocg_slam run` logs:
a CSV, a plot (SVG, no plotting library needed) and the growth after the first pass.

Usage: soak_report.py RUN_LOG OUT.csv OUT.svg PASS_FRAMES [--max-growth PERCENT]
PASS_FRAMES: frames of the preset; a pass is the preset forward and back (2 * PASS_FRAMES
- 2 frames). Growth is measured from the first sample after the first pass to the last.
Exit status 1 when the log holds no progress, or the resident memory grew more than
PERCENT after the first pass.
"""
import re
import sys

LINE = re.compile(r"progress: (?P<seconds>[0-9.]+) s, frame (?P<frame>\d+)/\d+, [0-9.]+ fps, "
                  r"(?P<keyframes>\d+) keyframes, (?P<map_points>\d+) map points, "
                  r"(?P<objects>\d+) objects, RSS (?P<rss_mb>[0-9.]+) MB"
                  r"(, heap (?P<heap_mb>[0-9.]+) MB)?")
COLUMNS = ["seconds", "frame", "pass", "keyframes", "map_points", "objects", "rss_mb", "heap_mb"]


def read_samples(log, pass_length):
    samples = []
    with open(log, errors="replace") as lines:
        for line in lines:
            match = LINE.search(line)
            if match:
                # heap_mb: the allocator's memory in use (logs of older builds have none)
                sample = {k: float(v) for k, v in match.groupdict().items() if v is not None}
                sample.setdefault("heap_mb", 0.0)
                sample["pass"] = int(sample["frame"] // pass_length) + 1
                samples.append(sample)
    return samples


def polyline(samples, key, x_scale, y_scale, left, bottom, colour):
    points = " ".join("%.1f,%.1f" % (left + s["seconds"] * x_scale, bottom - s[key] * y_scale)
                      for s in samples)
    return '<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' % (colour, points)


def panel(samples, keys, top, title, width=1000, height=260, left=70):
    """One plot: keys (name, colour, label) against minutes, each scaled to the panel."""
    bottom = top + height
    x_max = max(s["seconds"] for s in samples) or 1.0
    x_scale = (width - left - 20) / x_max
    parts = ['<text x="%d" y="%d" font-size="16">%s</text>' % (left, top - 8, title),
             '<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#888"/>'
             % (left, top, width - left - 20, height)]
    for minute in range(0, int(x_max / 60) + 1, max(1, int(x_max / 60 / 10) or 1)):
        x = left + minute * 60 * x_scale
        parts.append('<text x="%.0f" y="%d" font-size="12" text-anchor="middle">%d min</text>'
                     % (x, bottom + 16, minute))
    for row, (key, colour, label) in enumerate(keys):
        y_max = max(s[key] for s in samples) or 1.0
        y_scale = height / (1.1 * y_max)
        parts.append(polyline(samples, key, x_scale, y_scale, left, bottom, colour))
        parts.append('<text x="%d" y="%d" font-size="13" fill="%s">%s (max %.0f)</text>'
                     % (left + 10, top + 18 + 16 * row, colour, label, y_max))
    return parts


def write_svg(samples, path):
    parts = ['<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="680" '
             'font-family="sans-serif"><rect width="100%" height="100%" fill="white"/>']
    parts += panel(samples, [("rss_mb", "#c0392b", "resident memory, MB"),
                             ("heap_mb", "#e67e22", "of it, heap in use, MB")], 40,
                   "ocg_slam soak: resident memory and heap in use (each on its own scale)")
    parts += panel(samples, [("keyframes", "#2471a3", "keyframes"),
                             ("map_points", "#229954", "map points"),
                             ("objects", "#7d3c98", "objects")], 380,
                   "keyframes, map points and objects (each on its own scale)")
    parts.append("</svg>\n")
    with open(path, "w") as out:
        out.write("\n".join(parts))


def main():
    args = sys.argv[1:]
    max_growth = None
    if "--max-growth" in args:
        at = args.index("--max-growth")
        max_growth = float(args[at + 1])
        del args[at:at + 2]
    if len(args) != 4:
        sys.exit(__doc__)
    log, csv_path, svg_path, pass_frames = args[0], args[1], args[2], int(args[3])
    pass_length = 2 * pass_frames - 2
    samples = read_samples(log, pass_length)
    with open(csv_path, "w") as csv:
        csv.write(",".join(COLUMNS) + "\n")
        for s in samples:
            csv.write(",".join("%g" % s[c] for c in COLUMNS) + "\n")
    if not samples:
        print("soak: the run logged no progress (see %s)" % log)
        return 1
    write_svg(samples, svg_path)
    print("soak: %d samples in %s, plot %s" % (len(samples), csv_path, svg_path))
    last = samples[-1]
    after = [s for s in samples if s["frame"] >= pass_length]
    if len(after) < 2:
        print("soak: the run did not get past its first pass (%d of %d frames): no growth to "
              "measure" % (last["frame"], pass_length))
        return 0
    first = after[0]
    minutes = (last["seconds"] - first["seconds"]) / 60.0
    growth = 100.0 * (last["rss_mb"] - first["rss_mb"]) / first["rss_mb"]
    print("soak: after the first pass (frame %d at %.0f s) to the end (frame %d at %.0f s, "
          "%.1f passes):" % (first["frame"], first["seconds"], last["frame"], last["seconds"],
                             last["frame"] / pass_length))
    print("  resident memory %.0f -> %.0f MB (%+.1f %%, %+.2f MB/min)"
          % (first["rss_mb"], last["rss_mb"], growth,
             (last["rss_mb"] - first["rss_mb"]) / minutes if minutes > 0 else 0.0))
    if last["heap_mb"] > 0:
        print("  heap in use %.0f -> %.0f MB (%+.2f MB/min)"
              % (first["heap_mb"], last["heap_mb"],
                 (last["heap_mb"] - first["heap_mb"]) / minutes if minutes > 0 else 0.0))
    for key in ("keyframes", "map_points", "objects"):
        print("  %s %d -> %d" % (key.replace("_", " "), first[key], last[key]))
    if max_growth is not None and growth > max_growth:
        print("soak: FAILED: resident memory grew %.1f %% after the first pass (at most %.1f %%)"
              % (growth, max_growth))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
