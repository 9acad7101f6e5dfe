#!/usr/bin/env python3
"""SLAM speed bench: one `ocg_slam run`, its per-stage timings, and optionally a profile.

Runs the SLAM system (no objects) on a generated preset or on a sequence folder and
prints, from the run's run.json:
  - tracking per frame (feature extraction included): median, p95, max [ms];
  - local mapping per keyframe and local bundle adjustment per keyframe: median, p95 [ms];
  - wall time, frames tracked, keyframes;
and with --profile, where the CPU time goes: `perf record` over the whole run, the
functions with the largest share of samples (`perf report`, no call graph), and the same
grouped by thread, so that tracking and local mapping can be told apart in threaded mode.

Issue 17 point 6 goals, on one core with nothing else running (--cores 1):
tracking median <= 15 ms at 1000 features on 640x480 (TUM-like) and <= 30 ms at 2000
features on 1226x370 (KITTI); local BA median <= 100 ms per keyframe. The bench only
reports the figures; it never fails on a slow machine.

Examples:
  bench/slam_speed.py --preset smoke --look realistic --cores 1
  bench/slam_speed.py --sequence ../shared/data/kitti_07_first160 \\
      --settings ../shared/data/kitti_07_first160/orbslam2_KITTI04-12.yaml --cores 1 --profile
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

SOURCE_DIR = Path(__file__).resolve().parent.parent
STAGES = [
    ("tracking_per_frame", "tracking per frame"),
    ("local_mapping_per_keyframe", "local mapping per keyframe"),
    ("local_ba_per_keyframe", "local BA per keyframe"),
]


class BenchError(Exception):
    pass


def parse_args(argv):
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        epilog="\n\n".join(__doc__.split("\n\n")[1:]),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--build", type=Path, default=SOURCE_DIR / "build",
                        help="build folder holding tools/ocg_slam and tools/ocg_synth "
                             "(default: %(default)s)")
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--preset", default=None,
                        help="render this generator preset into a temporary folder "
                             "(default: smoke when no --sequence is given)")
    source.add_argument("--sequence", type=Path,
                        help="a sequence folder (TUM layout: rgb.txt and rgb/); needs --settings")
    parser.add_argument("--settings", type=Path,
                        help="settings file (ours or ORB-SLAM2's); default for a preset: "
                             "its camera.yaml")
    parser.add_argument("--look", choices=["procedural", "realistic"],
                        help="with --preset: the generator's look (default: the preset's)")
    parser.add_argument("--frames", type=int, default=0,
                        help="use only the first N frames (0: all)")
    parser.add_argument("--features", type=int, default=0,
                        help="ORBextractor.nFeatures (0: the settings' value, 1000 if unset)")
    parser.add_argument("--threaded", action="store_true",
                        help="System.sequential: false (local mapping and loop closing on "
                             "their own threads)")
    parser.add_argument("--cores", type=int, default=0,
                        help="pin the run to the first N CPU cores (0: no pinning); "
                             "issue 17's speed goals are for --cores 1")
    parser.add_argument("--profile", action="store_true",
                        help="record the run with `perf record` (Debian package linux-perf) "
                             "and print the functions and threads that take the time")
    parser.add_argument("--profile-frequency", type=int, default=99,
                        help="with --profile: samples per second (default: %(default)s)")
    parser.add_argument("--top", type=int, default=25,
                        help="with --profile: how many functions to list (default: %(default)s)")
    parser.add_argument("--json", type=Path,
                        help="also write the figures to this JSON file")
    parser.add_argument("--keep", type=Path,
                        help="keep the run folder (sequence, settings, SLAM output) here "
                             "instead of deleting it")
    args = parser.parse_args(argv)
    if args.sequence is not None and args.settings is None:
        parser.error("--sequence needs --settings")
    if args.look is not None and args.sequence is not None:
        parser.error("--look applies to a generated --preset only")
    if args.frames < 0 or args.features < 0 or args.cores < 0 or args.top <= 0:
        parser.error("--frames, --features and --cores take a number >= 0, --top one > 0")
    if args.preset is None and args.sequence is None:
        args.preset = "smoke"
    return args


def tool(build, name):
    path = build / "tools" / name
    if not os.access(path, os.X_OK):
        raise BenchError(f"{path} not found: build the project first (tools/test.sh) "
                         "or pass --build")
    return path


def override_key(text, key, value):
    """Sets a flat settings key (Section.name), replacing an existing flat line."""
    pattern = re.compile(rf"^{re.escape(key)}\s*:.*$", re.MULTILINE)
    line = f"{key}: {value}"
    if pattern.search(text):
        return pattern.sub(line, text, count=1)
    section, name = key.split(".", 1)
    if re.search(rf"^{re.escape(section)}\s*:\s*$", text, re.MULTILINE):
        # A nested section ("ORBextractor:\n  nFeatures: 1000"): a flat line for a key the
        # section already holds would be refused as given twice, so change it in place.
        nested = re.compile(
            rf"(^{re.escape(section)}\s*:\s*\n(?:[ \t]+.*\n)*?[ \t]+){re.escape(name)}\s*:.*$",
            re.MULTILINE)
        if nested.search(text):
            return nested.sub(rf"\g<1>{name}: {value}", text, count=1)
    return text.rstrip("\n") + "\n" + line + "\n"


def pin(cores):
    if cores <= 0:
        return None
    available = sorted(os.sched_getaffinity(0))
    if cores > len(available):
        raise BenchError(f"--cores {cores}: only {len(available)} cores are available")
    chosen = set(available[:cores])
    return lambda: os.sched_setaffinity(0, chosen)


def run(command, preexec=None, quiet=True):
    result = subprocess.run([str(c) for c in command], preexec_fn=preexec,
                            stdout=subprocess.PIPE if quiet else None,
                            stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        raise BenchError(f"{Path(str(command[0])).name} failed (exit {result.returncode}):\n"
                         f"{result.stderr.strip()}")
    return result


def perf_tables(perf, data, top):
    """Shares of the CPU samples: per thread, per function with what it calls (inclusive,
    from the DWARF call graphs) and per function alone (self)."""
    def report(*options):
        out = run([perf, "report", "--stdio", "-i", data, "-g", "none", "-t", "|",
                   "--percent-limit", "0.5", *options]).stdout
        rows = []
        for line in out.splitlines():
            if not line.strip() or line.startswith("#"):
                continue
            fields = [f.strip() for f in line.split("|")]
            try:
                rows.append([float(fields[0].rstrip("%"))] + fields[1:])
            except ValueError:
                continue
        return rows

    threads = [(r[0], r[1]) for r in report("--no-children", "--sort", "comm")]

    def name_of(symbol):
        return re.sub(r"^\[[.k]\]\s*", "", symbol)

    # Frames every sample passes through (process start, the tool's main, std::function
    # trampolines) and unresolved addresses say nothing about where the time goes.
    uninformative = re.compile(r"^(0x[0-9a-f]+|main|_start|__libc_start.*|__clone.*|"
                               r"start_thread|ocg::tools::.*|main::.*|std::.*|"
                               r"execute_native_thread_routine|\[unknown\])")
    inclusive = []
    for row in report("--children", "--sort", "sym"):
        symbol = name_of(row[2])
        if "[k]" in row[2] or uninformative.match(symbol):
            continue
        if any(symbol == seen for _, seen in inclusive):
            continue  # one name for several copies (inlined, or in two libraries)
        inclusive.append((row[0], symbol))

    alone = {}
    for row in report("--no-children", "--sort", "dso,sym"):
        dso, symbol = row[1], name_of(row[2])
        key = f"{dso} (unnamed)" if symbol.startswith("0x") else f"{symbol} ({dso})"
        alone[key] = alone.get(key, 0.0) + row[0]
    self_time = sorted(((share, name) for name, share in alone.items()), reverse=True)
    return {"threads": threads, "inclusive": inclusive[:top], "self": self_time[:top]}


def main(argv):
    args = parse_args(argv)
    slam = tool(args.build, "ocg_slam")
    perf = None
    if args.profile:
        perf = shutil.which("perf")
        if perf is None:
            raise BenchError("--profile needs perf: apt-get install linux-perf")
    if args.sequence is not None:
        if not (args.sequence / "rgb.txt").is_file():
            raise BenchError(f"{args.sequence}: no rgb.txt (a TUM-layout sequence folder)")
        if not args.settings.is_file():
            raise BenchError(f"{args.settings}: settings file not found")

    pinning = pin(args.cores)  # checked before rendering: a wrong count fails at once
    work = Path(tempfile.mkdtemp(prefix="slam_speed."))
    try:
        if args.preset is not None:
            sequence = work / "seq"
            command = [tool(args.build, "ocg_synth"), "--preset", args.preset, "--out", sequence,
                       "--keyframe-interval", 0, "--log-level", "warn"]
            if args.look:
                command += ["--look", args.look]
            if args.frames:
                command += ["--frames", args.frames]
            print(f"rendering preset {args.preset} ...", file=sys.stderr, flush=True)
            run(command)
            settings_text = (args.settings or sequence / "camera.yaml").read_text()
        else:
            sequence = args.sequence
            settings_text = args.settings.read_text()
        settings_text = override_key(settings_text, "System.sequential",
                                     "false" if args.threaded else "true")
        if args.features:
            settings_text = override_key(settings_text, "ORBextractor.nFeatures", args.features)
        settings = work / "settings.yaml"
        settings.write_text(settings_text)

        out = work / "slam"
        command = [slam, "run", "--settings", settings, "--sequence", sequence, "--out", out,
                   "--log-level", "warn", "--snapshots", "none"]
        if args.frames:
            command += ["--max-frames", args.frames]
        if perf:
            data = work / "perf.data"
            # DWARF unwinding: the release build has no frame pointers. 99 Hz keeps the
            # stack samples of a minutes-long run at some hundred MB.
            command = [perf, "record", "-q", "-F", str(args.profile_frequency),
                       "--call-graph", "dwarf,16384", "-o", data, "--"] + command
        print("running ocg_slam ...", file=sys.stderr, flush=True)
        run(command, preexec=pinning)

        report = json.loads((out / "run.json").read_text())
        figures = {
            "sequence": str(args.preset or args.sequence),
            "mode": report["mode"],
            "cores": args.cores or len(os.sched_getaffinity(0)),
            "features": report["orb"]["features"] if "orb" in report and
                        "features" in report["orb"] else args.features or None,
            "image": f"{report['camera']['width']}x{report['camera']['height']}",
            "frames": report["frames"],
            "frames_tracked": report["frames_tracked"],
            "keyframes": report["keyframes"],
            "wall_seconds": report["wall_seconds"],
            "timing": report["timing"],
        }
        if perf:
            figures["profile"] = perf_tables(perf, data, args.top)
        if args.keep:
            if args.keep.exists():
                shutil.rmtree(args.keep)
            shutil.copytree(work, args.keep)
    finally:
        shutil.rmtree(work, ignore_errors=True)

    print(f"{figures['sequence']}: {figures['image']}, {figures['features']} features, "
          f"{figures['mode']} mode, {figures['cores']} core(s)")
    for key, label in STAGES:
        t = figures["timing"][key]
        if t["count"] == 0:
            print(f"  {label:28s} (not measured in this mode)")
            continue
        print(f"  {label:28s} median {t['median_ms']:7.2f} ms   p95 {t['p95_ms']:7.2f} ms   "
              f"max {t['max_ms']:7.2f} ms   (n = {t['count']})")
    print(f"  wall {figures['wall_seconds']:.1f} s, {figures['frames_tracked']} of "
          f"{figures['frames']} frames tracked, {figures['keyframes']} keyframes")
    if "profile" in figures:
        profile = figures["profile"]
        print("  CPU samples by thread:")
        for share, name in profile["threads"]:
            print(f"    {share:6.2f} %  {name}")
        print("  functions with what they call (share of all samples):")
        for share, name in profile["inclusive"]:
            print(f"    {share:6.2f} %  {name}")
        print("  functions alone:")
        for share, name in profile["self"]:
            print(f"    {share:6.2f} %  {name}")
    if args.json:
        partial = args.json.with_name(args.json.name + ".partial")
        partial.write_text(json.dumps(figures, indent=2) + "\n")
        partial.replace(args.json)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except BenchError as error:
        print(f"slam_speed: {error}", file=sys.stderr)
        sys.exit(1)
