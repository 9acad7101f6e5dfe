#!/usr/bin/env python3
"""check_identical: are a build's sequential outputs byte for byte those of a baseline?

Usage:
  tools/check_identical.py record  BUILD_DIR OUT [--cache DIR] [--only RUN,...] [--frames N]
                                   [--resume]
  tools/check_identical.py compare BUILD_DIR OUT [--work DIR] [--only RUN,...] [--ignore GLOB]
  tools/check_identical.py diff    BEFORE_DIR AFTER_DIR [--ignore GLOB]
  tools/check_identical.py list

A refactoring must not change what a run writes. `record` runs a fixed set of runs with
the tools of BUILD_DIR (BUILD_DIR/tools/ocg_slam, ocg_synth) and keeps their outputs in
OUT/before/ with their SHA-256 in OUT/manifest.json. `compare` runs the same set, on the
same inputs, with another build into OUT/after/ (or --work) and prints, per run and file,
`identical` or how the file differs (sizes, line counts, the first differing line, for
JSON the first differing key). `diff` compares two run folders already written.

The set (every run sequential, the default settings but for the OCG mode):
  preset_P        ocg_slam run on `ocg_synth --preset P --detector realistic` (seed 1) with
                  its detections, --modes paper,improved, --save-map; P in smoke,
                  straight_1, straight_2, round_1, round_2, desk_static
  kitti_07        ocg_slam run on KITTI 07, first 160 frames, --save-map (no detections)
  fr3_pose_given  ocg_slam objects on TUM fr3 long_office: ground-truth poses, the real
                  detections of all 2,585 frames, modes paper and improved (--frames
                  does not apply)
  session_pair    session 0 on `session_a` (seed 1), saved; session 1 on `session_b` of it
                  (seed 11) with --load-map, saved again (docs/sessions.md)
Compared: every file a run writes but run.json (timings) and the logs: trajectories,
objects.json, changes.json, ocg.json, ocg_observations.jsonl, map_points.ply, map files.

Inputs are generated once, by the recording build's ocg_synth, into the cache folder
(--cache, else $OCG_IDENTICAL_CACHE, else OUT/inputs) and reused by `compare` (their
checksums are checked): the generator is not what is compared. Real data comes from
--data, else $OCG_SHARED_DATA, else ../shared/data beside the source tree. The default
vocabulary is copied into the cache and given to every run through $OCG_VOCABULARY: a map
file records the vocabulary's path, which would otherwise differ between worktrees.

The whole set (about 19,000 frames of SLAM) takes one to three hours on a shared 2-core
machine; run it under `nice -n 10`. The manifest is written after every run, shortest
first: an interrupted recording keeps what it finished and `record --resume` goes on.
Exit status: 0 every compared file identical, 1 some differ (or a run failed in compare),
2 a usage or input error.
"""
import argparse
import datetime
import fnmatch
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.realpath(__file__))
SOURCE_DIR = os.path.dirname(HERE)
MANIFEST_FORMAT = "ocg-check-identical"
MANIFEST_VERSION = 1
PRESETS = ["smoke", "straight_1", "straight_2", "round_1", "round_2", "desk_static"]
PRESET_MODES = "paper,improved"
POSE_GIVEN_MODES = ["paper", "improved"]
# Shortest first, so that an interrupted recording (resumed with --resume) keeps the most.
RUNS = ["preset_smoke", "kitti_07", "fr3_pose_given", "session_pair", "preset_desk_static",
        "preset_round_1", "preset_straight_1", "preset_straight_2", "preset_round_2"]
# Written by a run but not compared: timings and host details, and our own logs.
NOT_COMPARED = {"run.json", "log.txt"}
VOCABULARY_FILE = "ocg_orb_vocabulary.ocgvoc"


class UsageError(Exception):
    """A wrong argument or a missing input: printed as one line, exit status 2."""


def log(message):
    print(message, flush=True)


def sha256(path):
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def write_json_atomically(path, value):
    temporary = path + ".tmp"
    with open(temporary, "w") as f:
        json.dump(value, f, indent=2, sort_keys=True)
        f.write("\n")
    os.replace(temporary, path)


# ---------------------------------------------------------------------------------------
# Inputs


class Inputs:
    """Where the runs' inputs are: the cache of generated sequences, real data, tools."""

    def __init__(self, build_dir, cache_dir, data_dir, frames):
        self.build_dir = os.path.realpath(build_dir)  # names match the manifest's keys
        self.cache = os.path.realpath(cache_dir)
        self.data = os.path.realpath(data_dir) if data_dir else None
        self.frames = frames

    def tool(self, name):
        path = os.path.join(self.build_dir, "tools", name)
        if not os.access(path, os.X_OK):
            raise UsageError("%s is not there or not executable: build the targets ocg_slam "
                             "and ocg_synth in %s first" % (path, self.build_dir))
        return path

    def sequence(self, name):
        return os.path.join(self.cache, name if self.frames == 0 else
                            "%s_first%d" % (name, self.frames))

    def real(self, folder):
        if self.data is None or not os.path.isdir(os.path.join(self.data, folder)):
            raise UsageError("real data folder '%s' not found under %s: give --data or "
                             "$OCG_SHARED_DATA, or leave the run out with --only"
                             % (folder, self.data or "(no data folder)"))
        return os.path.join(self.data, folder)

    def vocabulary(self):
        return os.path.join(self.cache, "vocabulary", VOCABULARY_FILE)


def source_dir_of_build(build_dir):
    """The source tree a CMake build folder was configured from (its CMakeCache.txt)."""
    try:
        with open(os.path.join(build_dir, "CMakeCache.txt")) as f:
            for line in f:
                if line.startswith("CMAKE_HOME_DIRECTORY:"):
                    return line.split("=", 1)[1].strip()
    except OSError:
        pass
    return None


def commit_of(source_dir):
    if not source_dir:
        return None
    try:
        commit = subprocess.run(["git", "-C", source_dir, "rev-parse", "HEAD"], check=True,
                                capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", source_dir, "status", "--porcelain",
                                "--untracked-files=no"], check=True, capture_output=True,
                               text=True).stdout.strip()
        return commit + ("+uncommitted" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return None


def run_logged(argv, log_path, env):
    """Runs argv with stdout and stderr appended to log_path; raises on failure."""
    with open(log_path, "a") as out:
        out.write("$ " + " ".join(argv) + "\n")
        out.flush()
        result = subprocess.run(argv, stdout=out, stderr=subprocess.STDOUT, env=env)
    if result.returncode != 0:
        with open(log_path) as f:
            tail = f.read().splitlines()[-15:]
        raise RuntimeError("command failed with status %d: %s\n  last lines of %s:\n    %s"
                           % (result.returncode, " ".join(argv), log_path,
                              "\n    ".join(tail)))


def generate(inputs, name, argv_after_tool, env):
    """ocg_synth into the cache once; a folder without its .complete marker is redone."""
    folder = inputs.sequence(name)
    marker = os.path.join(folder, ".complete")
    if os.path.isfile(marker):
        return folder
    if os.path.exists(folder):
        shutil.rmtree(folder)
    os.makedirs(inputs.cache, exist_ok=True)
    log_path = folder + ".log"
    if os.path.exists(log_path):
        os.remove(log_path)
    argv = [inputs.tool("ocg_synth")] + argv_after_tool + ["--out", folder,
                                                           "--log-level", "warn"]
    if inputs.frames:
        argv += ["--frames", str(inputs.frames)]
    started = time.time()
    log("  generating %s (once, into the cache)" % folder)
    run_logged(argv, log_path, env)
    open(marker, "w").close()
    log("  generated in %.0f s" % (time.time() - started))
    return folder


def prepare_vocabulary(inputs):
    """Copies the build's default vocabulary into the cache once."""
    target = inputs.vocabulary()
    if os.path.isfile(target):
        return target
    source = source_dir_of_build(inputs.build_dir)
    candidate = os.path.join(source or SOURCE_DIR, "thirdparty", "vocabulary", VOCABULARY_FILE)
    if not os.path.isfile(candidate):
        raise UsageError("no default vocabulary at %s (see thirdparty/README.md)" % candidate)
    os.makedirs(os.path.dirname(target), exist_ok=True)
    shutil.copyfile(candidate, target + ".tmp")
    os.replace(target + ".tmp", target)
    return target


def input_checksums(folder):
    """Checksums of a generated sequence's text files and detections (not its images)."""
    sums = {}
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if d not in ("rgb", "depth"))
        for name in sorted(files):
            if name.endswith((".png", ".jpg", ".log")) or name == ".complete":
                continue
            path = os.path.join(root, name)
            sums[os.path.relpath(path, folder)] = sha256(path)
    return sums


# ---------------------------------------------------------------------------------------
# The runs


def ocg_slam_run(inputs, sequence, settings, out, extra):
    return [inputs.tool("ocg_slam"), "run", "--settings", settings, "--sequence", sequence,
            "--snapshots", "none", "--out", out, "--log-level", "warn"] + extra


def execute(run, inputs, out, env):
    """Runs one run of the set into the folder `out` (made empty first). Returns the
    input folders it used (for their checksums)."""
    if os.path.exists(out):
        shutil.rmtree(out)
    os.makedirs(out)
    log_path = os.path.join(out, "log.txt")
    if run.startswith("preset_"):
        preset = run[len("preset_"):]
        sequence = generate(inputs, preset, ["--preset", preset, "--detector", "realistic"], env)
        run_logged(ocg_slam_run(inputs, sequence, os.path.join(sequence, "camera.yaml"), out,
                                ["--detections", os.path.join(sequence, "detections"),
                                 "--modes", PRESET_MODES,
                                 "--save-map", os.path.join(out, "map.ocgmap")]),
                   log_path, env)
        return {preset: sequence}
    if run == "kitti_07":
        data = inputs.real("kitti_07_first160")
        argv = ocg_slam_run(inputs, data, os.path.join(data, "orbslam2_KITTI04-12.yaml"), out,
                            ["--save-map", os.path.join(out, "map.ocgmap")])
        if inputs.frames:
            argv += ["--max-frames", str(inputs.frames)]
        run_logged(argv, log_path, env)
        return {}
    if run == "fr3_pose_given":
        data = inputs.real("tum_fr3_long_office")
        for mode in POSE_GIVEN_MODES:
            # Always every frame (--frames does not apply): pose-given takes seconds, and
            # the frame list's images give the image size the settings file lacks.
            frames = os.path.join(data, "rgb_all_frames.txt")
            run_logged([inputs.tool("ocg_slam"), "objects",
                        "--trajectory", os.path.join(data, "groundtruth.txt"),
                        "--detections", os.path.join(data, "detections"), "--frames", frames,
                        "--settings", os.path.join(data, "orbslam2_TUM3.yaml"),
                        "--mode", mode, "--out", os.path.join(out, mode),
                        "--log-level", "warn"], log_path, env)
        return {}
    if run == "session_pair":
        first = generate(inputs, "session_a", ["--preset", "session_a", "--seed", "1"], env)
        second = generate(inputs, "session_b", ["--preset", "session_b", "--session-of", first,
                                                "--seed", "11"], env)
        run_logged(ocg_slam_run(inputs, first, os.path.join(first, "camera.yaml"),
                                os.path.join(out, "session0"),
                                ["--detections", os.path.join(first, "detections"),
                                 "--save-map", os.path.join(out, "session0.ocgmap")]),
                   log_path, env)
        run_logged(ocg_slam_run(inputs, second, os.path.join(first, "camera.yaml"),
                                os.path.join(out, "session1"),
                                ["--detections", os.path.join(second, "detections"),
                                 "--load-map", os.path.join(out, "session0.ocgmap"),
                                 "--save-map", os.path.join(out, "session1.ocgmap")]),
                   log_path, env)
        return {"session_a": first, "session_b": second}
    raise UsageError("unknown run '%s' (see `check_identical.py list`)" % run)


def output_checksums(folder):
    sums = {}
    for root, dirs, files in os.walk(folder):
        dirs.sort()
        for name in sorted(files):
            if name in NOT_COMPARED:
                continue
            path = os.path.join(root, name)
            sums[os.path.relpath(path, folder)] = sha256(path)
    return sums


def run_environment(inputs):
    env = dict(os.environ)
    env["OCG_VOCABULARY"] = prepare_vocabulary(inputs)
    return env


def run_all(runs, inputs, folder, stop_on_error, on_done=None):
    """Runs `runs` into folder/<run>; returns {run: {"files", "inputs", "seconds"} or
    {"error"}}; on_done(run, result) after each run that succeeded."""
    env = run_environment(inputs)
    results = {}
    total_started = time.time()
    for index, run in enumerate(runs, 1):
        log("[%d/%d] %s (%s, %.0f s so far)" % (index, len(runs), run,
                                                datetime.datetime.now().strftime("%H:%M:%S"),
                                                time.time() - total_started))
        started = time.time()
        try:
            used = execute(run, inputs, os.path.join(folder, run), env)
        except (RuntimeError, OSError) as error:
            if stop_on_error:
                raise
            log("  FAILED: %s" % error)
            results[run] = {"error": str(error)}
            continue
        seconds = time.time() - started
        files = output_checksums(os.path.join(folder, run))
        results[run] = {"files": files, "seconds": round(seconds, 1),
                        "inputs": {name: input_checksums(path) for name, path in used.items()}}
        log("  done in %.0f s, %d files" % (seconds, len(files)))
        if on_done:
            on_done(run, results[run])
    return results


# ---------------------------------------------------------------------------------------
# Comparing files


def first_json_difference(a, b, path="$"):
    """The path of the first place two JSON values differ, and a short how."""
    if type(a) is not type(b):
        return path, "%s vs %s" % (type(a).__name__, type(b).__name__)
    if isinstance(a, dict):
        for key in list(a.keys()) + [k for k in b.keys() if k not in a]:
            if key not in b:
                return "%s.%s" % (path, key), "only before"
            if key not in a:
                return "%s.%s" % (path, key), "only after"
            found = first_json_difference(a[key], b[key], "%s.%s" % (path, key))
            if found:
                return found
        return None
    if isinstance(a, list):
        for i, (x, y) in enumerate(zip(a, b)):
            found = first_json_difference(x, y, "%s[%d]" % (path, i))
            if found:
                return found
        if len(a) != len(b):
            return path, "%d vs %d items" % (len(a), len(b))
        return None
    if a != b:
        return path, "%s vs %s" % (short(json.dumps(a)), short(json.dumps(b)))
    return None


def short(text, limit=100):
    text = text.rstrip("\n")
    return text if len(text) <= limit else text[:limit] + "..."


def how_files_differ(before, after):
    """One or two lines saying how two differing files differ."""
    with open(before, "rb") as f:
        a = f.read()
    with open(after, "rb") as f:
        b = f.read()
    try:
        text_a, text_b = a.decode("utf-8"), b.decode("utf-8")
    except UnicodeDecodeError:
        offset = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
        return ["binary, %d -> %d bytes, first difference at byte %d" % (len(a), len(b), offset)]
    lines_a, lines_b = text_a.splitlines(), text_b.splitlines()
    differing = sum(1 for x, y in zip(lines_a, lines_b) if x != y) + abs(len(lines_a) -
                                                                          len(lines_b))
    first = next((i for i, (x, y) in enumerate(zip(lines_a, lines_b)) if x != y),
                 min(len(lines_a), len(lines_b)))
    how = ["%d -> %d lines, %d differ; first at line %d:" % (len(lines_a), len(lines_b),
                                                             differing, first + 1),
           "  before: %s" % (short(lines_a[first]) if first < len(lines_a) else "(end)"),
           "  after:  %s" % (short(lines_b[first]) if first < len(lines_b) else "(end)")]
    if before.endswith(".json"):
        try:
            found = first_json_difference(json.loads(text_a), json.loads(text_b))
            if found:
                how.append("  first JSON difference at %s: %s" % found)
        except ValueError:
            pass
    return how


def compare_folders(before, after, names_before=None, names_after=None, ignore=()):
    """Compares two run folders; returns (lines to print, number of differing files).
    Files whose path matches a glob of `ignore` are listed as ignored."""
    names_before = names_before if names_before is not None else output_checksums(before)
    names_after = names_after if names_after is not None else output_checksums(after)
    lines, differing = [], 0
    for name in sorted(set(names_before) | set(names_after)):
        if any(fnmatch.fnmatch(name, pattern) for pattern in ignore):
            lines.append("  %-44s ignored (--ignore)" % name)
        elif name not in names_after:
            lines.append("  %-44s missing after" % name)
            differing += 1
        elif name not in names_before:
            lines.append("  %-44s new after (not in the baseline)" % name)
            differing += 1
        elif names_before[name] == names_after[name]:
            lines.append("  %-44s identical" % name)
        else:
            differing += 1
            path_before = os.path.join(before, name)
            if os.path.isfile(path_before):
                how = how_files_differ(path_before, os.path.join(after, name))
            else:
                how = ["(the baseline keeps its checksum only)"]
            lines.append("  %-44s differs: %s" % (name, how[0]))
            lines.extend("  " + " " * 44 + " " + line for line in how[1:])
    return lines, differing


# ---------------------------------------------------------------------------------------
# Commands


def parse_only(text):
    if not text:
        return list(RUNS)
    runs = [r.strip() for r in text.split(",") if r.strip()]
    unknown = [r for r in runs if r not in RUNS]
    if unknown:
        raise UsageError("--only: unknown run(s) %s; the runs are %s"
                         % (", ".join(unknown), ", ".join(RUNS)))
    return runs


def default_data_dir():
    if os.environ.get("OCG_SHARED_DATA"):
        return os.environ["OCG_SHARED_DATA"]
    candidate = os.path.join(SOURCE_DIR, "..", "shared", "data")
    return candidate if os.path.isdir(candidate) else None


def command_record(args):
    out = os.path.realpath(args.out)
    manifest_path = os.path.join(out, "manifest.json")
    if os.path.exists(manifest_path) and not (args.overwrite or args.resume):
        raise UsageError("%s already holds a recorded baseline (manifest.json): give another "
                         "OUT, --resume or --overwrite" % out)
    if args.frames < 0:
        raise UsageError("--frames must be 0 (all) or positive, got %d" % args.frames)
    runs = parse_only(args.only)
    cache = args.cache or os.environ.get("OCG_IDENTICAL_CACHE") or os.path.join(out, "inputs")
    inputs = Inputs(args.build_dir, cache, args.data or default_data_dir(), args.frames)
    inputs.tool("ocg_slam"), inputs.tool("ocg_synth")
    for run in runs:  # real data checked before the first long run
        if run == "kitti_07":
            inputs.real("kitti_07_first160")
        if run == "fr3_pose_given":
            inputs.real("tum_fr3_long_office")
    source = source_dir_of_build(inputs.build_dir)
    manifest = {
        "format": MANIFEST_FORMAT, "version": MANIFEST_VERSION,
        "recorded": datetime.datetime.now().isoformat(timespec="seconds"),
        "build_dir": inputs.build_dir, "source_dir": source, "commit": commit_of(source),
        "cache": inputs.cache, "data": inputs.data, "frames": inputs.frames,
        "vocabulary_sha256": None, "runs": {}, "complete": False}
    if args.resume and os.path.exists(manifest_path):
        manifest = read_manifest(out)
        for key in ("build_dir", "cache", "frames"):
            if manifest[key] != getattr(inputs, key):
                raise UsageError("--resume: %s was recorded with %s %s, not %s"
                                 % (manifest_path, key, manifest[key], getattr(inputs, key)))
        if commit_of(source) != manifest["commit"]:
            log("warning: the build's source is at %s, the baseline's manifest says %s"
                % (commit_of(source), manifest["commit"]))
        inputs.data = manifest["data"]
    elif os.path.exists(manifest_path):
        os.remove(manifest_path)
    os.makedirs(out, exist_ok=True)
    left = [run for run in runs if run not in manifest["runs"]]
    log("recording %d run(s) with %s into %s (inputs: %s)%s"
        % (len(left), inputs.build_dir, out, inputs.cache,
           "; %d kept from before" % (len(runs) - len(left)) if len(left) < len(runs) else ""))

    def keep(run, result):  # the manifest after every run: an interrupted recording resumes
        manifest["runs"][run] = result
        manifest["vocabulary_sha256"] = sha256(inputs.vocabulary())
        manifest["complete"] = all(r in manifest["runs"] for r in RUNS)
        write_json_atomically(manifest_path, manifest)

    run_all(left, inputs, os.path.join(out, "before"), stop_on_error=True, on_done=keep)
    log("recorded: %s (commit %s), %d of %d runs%s"
        % (manifest_path, manifest["commit"], len(manifest["runs"]), len(RUNS),
           "" if manifest.get("complete") else "; the rest with `record ... --resume`"))
    log("compare a build with:\n  nice -n 10 %s compare BUILD_DIR %s"
        % (os.path.relpath(os.path.realpath(__file__)), out))
    return 0


def read_manifest(out):
    path = os.path.join(out, "manifest.json")
    try:
        with open(path) as f:
            manifest = json.load(f)
    except FileNotFoundError:
        raise UsageError("%s not found: record a baseline first (`record BUILD_DIR %s`)"
                         % (path, out))
    except ValueError as error:
        raise UsageError("%s: not JSON (%s)" % (path, error))
    if manifest.get("format") != MANIFEST_FORMAT or manifest.get("version") != MANIFEST_VERSION:
        raise UsageError("%s is not a check_identical manifest of version %d"
                         % (path, MANIFEST_VERSION))
    return manifest


def command_compare(args):
    out = os.path.realpath(args.out)
    manifest = read_manifest(out)
    recorded = list(manifest["runs"])
    runs = parse_only(args.only) if args.only else recorded
    missing = [r for r in runs if r not in recorded]
    if missing:
        raise UsageError("the baseline in %s has no run %s (it has %s)"
                         % (out, ", ".join(missing), ", ".join(recorded)))
    inputs = Inputs(args.build_dir, manifest["cache"], manifest["data"], manifest["frames"])
    inputs.tool("ocg_slam")
    if not os.path.isfile(inputs.vocabulary()) or \
            sha256(inputs.vocabulary()) != manifest["vocabulary_sha256"]:
        raise UsageError("the cached vocabulary %s is gone or changed since the recording"
                         % inputs.vocabulary())
    for run in runs:  # the inputs are those of the recording
        for name, sums in manifest["runs"][run]["inputs"].items():
            folder = inputs.sequence(name)
            if not os.path.isfile(os.path.join(folder, ".complete")):
                raise UsageError("input %s of run %s is gone from the cache: record again"
                                 % (folder, run))
            if input_checksums(folder) != sums:
                raise UsageError("input %s of run %s changed since the recording: record again"
                                 % (folder, run))
    work = os.path.realpath(args.work) if args.work else os.path.join(out, "after")
    log("comparing %d run(s) of %s with %s (baseline commit %s%s)"
        % (len(runs), inputs.build_dir, out, manifest.get("commit"),
           "" if manifest.get("complete") else
           "; the baseline holds %d of the %d runs" % (len(recorded), len(RUNS))))
    results = run_all(runs, inputs, work, stop_on_error=False)
    report, status = [], 0
    for run in runs:
        result = results[run]
        if "error" in result:
            report += ["%s: FAILED" % run, "  " + result["error"].replace("\n", "\n  ")]
            status = 1
            continue
        lines, differing = compare_folders(os.path.join(out, "before", run),
                                           os.path.join(work, run),
                                           manifest["runs"][run]["files"], result["files"],
                                           args.ignore or ())
        report.append("%s: %s" % (run, "identical" if differing == 0 else
                                  "%d file(s) differ" % differing))
        report += lines
        status = status or (1 if differing else 0)
    report.append("ALL IDENTICAL" if status == 0 else "SOME OUTPUTS DIFFER (see above)")
    log("\n".join(report))
    os.makedirs(work, exist_ok=True)
    with open(os.path.join(work, "report.txt"), "w") as f:
        f.write("\n".join(report) + "\n")
    return status


def command_diff(args):
    for folder in (args.before, args.after):
        if not os.path.isdir(folder):
            raise UsageError("%s is not a folder" % folder)
    lines, differing = compare_folders(args.before, args.after, ignore=args.ignore or ())
    log("\n".join(lines))
    log("ALL IDENTICAL" if differing == 0 else "%d file(s) differ" % differing)
    return 1 if differing else 0


def command_list(_):
    for run in RUNS:
        log(run)
    return 0


def main():
    parser = argparse.ArgumentParser(
        prog="check_identical.py", description=__doc__.split("\n\n")[1],
        epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    record = commands.add_parser("record", help="run the set and keep its outputs as the "
                                 "baseline")
    record.add_argument("build_dir", metavar="BUILD_DIR", help="a build folder (tools/ inside)")
    record.add_argument("out", metavar="OUT", help="the baseline's folder")
    record.add_argument("--cache", help="where generated inputs are kept (default: "
                        "$OCG_IDENTICAL_CACHE, else OUT/inputs)")
    record.add_argument("--data", help="real data folder (default: $OCG_SHARED_DATA, else "
                        "../shared/data beside the source tree)")
    record.add_argument("--only", help="comma-separated runs (default: all; see `list`)")
    record.add_argument("--frames", type=int, default=0,
                        help="only the first N frames of every sequence (0: all; for quick "
                        "checks, not the baseline)")
    record.add_argument("--overwrite", action="store_true", help="replace a recorded baseline")
    record.add_argument("--resume", action="store_true",
                        help="keep the runs OUT's manifest already holds (same build, commit "
                        "and cache) and record the others")
    compare = commands.add_parser("compare", help="run the set with another build and compare")
    compare.add_argument("build_dir", metavar="BUILD_DIR", help="a build folder (tools/ inside)")
    compare.add_argument("out", metavar="OUT", help="a folder `record` wrote")
    compare.add_argument("--only", help="comma-separated runs of the baseline (default: all)")
    compare.add_argument("--work", help="where the new outputs go (default: OUT/after, "
                         "replaced run by run)")
    diff = commands.add_parser("diff", help="compare two run folders already written")
    diff.add_argument("before", metavar="BEFORE_DIR")
    diff.add_argument("after", metavar="AFTER_DIR")
    for command in (compare, diff):
        command.add_argument("--ignore", action="append", metavar="GLOB",
                             help="leave files whose path in the run folder matches GLOB out "
                             "of the verdict (repeatable), e.g. '*.ocgmap' while map files "
                             "are known not to repeat")
    commands.add_parser("list", help="print the names of the runs")
    args = parser.parse_args()
    if not args.command:
        parser.print_help()
        return 2
    try:
        return {"record": command_record, "compare": command_compare, "diff": command_diff,
                "list": command_list}[args.command](args)
    except UsageError as error:
        print("check_identical.py: error: %s" % error, file=sys.stderr)
        return 2
    except RuntimeError as error:
        print("check_identical.py: %s" % error, file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("check_identical.py: interrupted", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
