"""The batch configuration (docs/batch.md): read, checked whole before any job starts,
and resolved (defaults filled, paths absolute) into the JSON the Snakefile reads.

Every error names the file and the key, e.g. `b.yaml: sequences[1].preset: unknown preset
'smok' (known: smoke, ...)`. Settings files and variant keys are checked by the product's
own reader (`ocg_slam settings --strict`), so the batch reads exactly what a run reads and a
misspelt key stops the batch with the key it most likely meant. Needs PyYAML (a dependency
of Debian's snakemake) for the batch file itself.
"""
import json
import os
import re
import subprocess

import yaml


MODES = ("off", "visibility", "paper", "improved", "fallback", "in_image", "guard")
EXECUTIONS = ("sequential", "threaded")
NAME = re.compile(r"^[A-Za-z0-9_.-]+$")
TOP_KEYS = {"out", "tools", "sequences", "modes", "variants", "executions", "repeats",
            "realtime", "max_dt"}
GENERATED_KEYS = {"name", "preset", "seed", "frames", "size", "detector", "snapshots", "set"}
DETECTORS = ("independent", "realistic")
USER_KEYS = {"name", "path", "format", "settings", "groundtruth", "detections", "detect",
             "objects_gt", "max_frames", "snapshots", "set"}
DETECT_KEYS = {"score", "model", "tile"}


class ConfigError(Exception):
    pass


def flatten(value, prefix, out):
    """{A: {b: v}} -> {"A.b": v}: variants may nest keys as settings files do."""
    if isinstance(value, dict):
        for key, item in value.items():
            flatten(item, "%s.%s" % (prefix, key) if prefix else str(key), out)
    else:
        out[prefix] = value
    return out


def settings_command(tools, base, overrides, sequential, write=None, image=None):
    """The ocg_slam settings command line of a run's settings: the sequence's settings file
    (None: the defaults), the variant's keys and System.sequential on top, checked strictly."""
    command = [os.path.join(tools, "ocg_slam"), "settings"]
    if base:
        command += [base, "--need-camera"]
    command.append("--strict")
    for key, value in overrides.items():
        command += ["--set", "%s=%s" % (key, json.dumps(value))]
    command += ["--set", "System.sequential=%s" % ("true" if sequential else "false")]
    if image:
        command += ["--image", image]
    if write:
        command += ["--write", write]
    return command


def _fail(source, key, message):
    raise ConfigError("%s: %s: %s" % (source, key, message))


def _path(source, key, base, value, kind, sequence=None):
    """A path relative to base (the configuration's folder). sequence: the sequence folder,
    named in the error when the path is found there instead (groundtruth: alone is relative
    to it, so `detections: detections` is an easy slip)."""
    if not isinstance(value, str) or not value:
        _fail(source, key, "expected a path")
    path = os.path.normpath(os.path.join(base, os.path.expanduser(value)))
    exists = {"file": os.path.isfile, "dir": os.path.isdir}.get(kind)
    if exists and not exists(path):
        message = "no such %s: %s" % ("file" if kind == "file" else "folder", path)
        if sequence and exists(os.path.join(sequence, value)):
            message += (" (relative to the configuration file; the sequence's own is %s: "
                        "give that path)" % os.path.normpath(os.path.join(sequence, value)))
        _fail(source, key, message)
    return path


def _whole(source, key, value, minimum):
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        _fail(source, key, "expected a whole number >= %d, got %r" % (minimum, value))
    return value


def _detect(source, key, base, value):
    """A sequence's `detect:` (true, or {score, model, tile}): the ocg_detect options of its
    detection job, or None for false."""
    if value is False:
        return None
    if value is True:
        value = {}
    if not isinstance(value, dict):
        _fail(source, key, "expected true or a mapping of ocg_detect options (%s)" %
              ", ".join(sorted(DETECT_KEYS)))
    extra = sorted(set(value) - DETECT_KEYS)
    if extra:
        _fail(source, "%s.%s" % (key, extra[0]), "unknown key (known: %s)" %
              ", ".join(sorted(DETECT_KEYS)))
    options = []
    if "score" in value:
        score = value["score"]
        if isinstance(score, bool) or not isinstance(score, (int, float)) or not 0 < score < 1:
            _fail(source, key + ".score", "expected a confidence in (0, 1), got %r" % (score,))
        options += ["--score", repr(float(score))]
    if "model" in value:
        options += ["--model", _path(source, key + ".model", base, value["model"], "file")]
    if "tile" in value:
        if value["tile"] not in ("auto", "off"):
            _fail(source, key + ".tile", "expected auto or off, got %r" % (value["tile"],))
        options += ["--tile", value["tile"]]
    return options


def _snapshots(source, key, value):
    if not isinstance(value, bool):
        _fail(source, key, "expected true (the runs draw their final snapshots) or false")
    return value


def _mode_ok(mode):
    if mode in ("off", "visibility", "paper", "improved"):
        return True
    return all(part in ("fallback", "in_image", "guard") for part in mode.split("+"))


def default_tools(script_dir):
    """Beside the wrapper when installed (bin/), else the build folder of the checkout."""
    if os.path.exists(os.path.join(script_dir, "ocg_slam")):
        return script_dir
    return os.path.normpath(os.path.join(script_dir, "..", "build", "tools"))


def _presets(tools):
    result = subprocess.run([os.path.join(tools, "ocg_synth"), "--list-presets"],
                            capture_output=True, text=True)
    return result.stdout.split() if result.returncode == 0 else []


def _first_image(source, key, path, form):
    """The sequence's first image, after checking that every image it lists exists (a run
    would stop at a missing one, after the frames before it)."""
    if form == "tum":
        listing, folder, separator = os.path.join(path, "rgb.txt"), path, None
    else:
        folder = os.path.join(path, "mav0", "cam0", "data")
        listing, separator = os.path.join(path, "mav0", "cam0", "data.csv"), ","
    if not os.path.isfile(listing):
        _fail(source, key + ".path", "not a %s sequence: %s is missing" % (
            "TUM" if form == "tum" else "EuRoC", listing))
    images = []
    with open(listing) as handle:
        for number, line in enumerate(handle, 1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            fields = [f.strip() for f in line.strip().split(separator)]
            if len(fields) < 2:
                _fail(source, key + ".path", "%s:%d: expected 'timestamp filename'" % (
                    listing, number))
            images.append((number, os.path.join(folder, fields[1])))
    if not images:
        _fail(source, key + ".path", "%s lists no image" % listing)
    for number, image in images:
        if not os.path.isfile(image):
            _fail(source, key + ".path", "%s:%d: no such image: %s" % (listing, number, image))
    return images[0][1]


def _check_settings(source, tools, sequences, variants):
    """Every sequence's settings file, and every variant over it, read as the runs will read
    them (ocg_slam settings --strict), before any job: an unknown key, a wrong value or
    settings of another camera stop the batch here, naming the key."""
    checked = {}
    for index, sequence in enumerate(sequences):
        base = None if sequence["generated"] else sequence["settings"]
        image = None if sequence["generated"] else sequence["first_image"]
        where = "sequences[%d].settings" % index
        own = sequence["set"]
        for name, overrides in [(None, {})] + list(variants.items()):
            if (base, image, json.dumps(own, sort_keys=True), name) in checked:
                continue
            checked[(base, image, json.dumps(own, sort_keys=True), name)] = True
            command = settings_command(tools, base, dict(own, **overrides), True, image=image)
            result = subprocess.run(command, capture_output=True, text=True)
            if result.returncode != 0:
                message = result.stderr.strip().replace("ocg_slam: error: ", "")
                if name is None:
                    _fail(source, "sequences[%d].set" % index if own else where, message)
                _fail(source, "variants.%s" % name, message + (
                    "" if base is None else " (over %s's settings)" % sequence["name"]))


def load(config_path, script_dir, out_override=None):
    """Returns the resolved batch (a dict) or raises ConfigError naming file and key."""
    source = config_path
    try:
        with open(config_path) as handle:
            raw = yaml.safe_load(handle)
    except OSError as error:
        raise ConfigError("%s: cannot read: %s" % (source, error.strerror))
    except yaml.YAMLError as error:
        raise ConfigError("%s: not YAML: %s" % (source, error))
    if not isinstance(raw, dict):
        raise ConfigError("%s: expected a mapping of keys (out, sequences, modes, ...)" % source)
    unknown = sorted(set(raw) - TOP_KEYS)
    if unknown:
        _fail(source, unknown[0], "unknown key (known: %s)" % ", ".join(sorted(TOP_KEYS)))
    base = os.path.dirname(os.path.abspath(config_path))

    tools = _path(source, "tools", base, raw["tools"], "dir") if "tools" in raw else \
        default_tools(script_dir)
    needed = ["ocg_slam", "ocg_eval"]
    sequences_raw = raw.get("sequences")
    if not isinstance(sequences_raw, list) or not sequences_raw:
        _fail(source, "sequences", "expected a non-empty list of sequences")
    if any(isinstance(s, dict) and "preset" in s for s in sequences_raw):
        needed.append("ocg_synth")
    if any(isinstance(s, dict) and s.get("detect") not in (None, False) for s in sequences_raw):
        needed.append("ocg_detect")
    for tool in needed:
        if not os.access(os.path.join(tools, tool), os.X_OK):
            _fail(source, "tools", "%s not found in %s (build it, or set tools: to the folder "
                  "with the OCG-SLAM programs)" % (tool, tools))
    presets = None

    sequences, names = [], set()
    for index, entry in enumerate(sequences_raw):
        key = "sequences[%d]" % index
        if not isinstance(entry, dict):
            _fail(source, key, "expected a mapping with preset: or path:")
        if ("preset" in entry) == ("path" in entry):
            _fail(source, key, "give either preset: (generated) or path: (your TUM/EuRoC folder)")
        if "preset" in entry:
            extra = sorted(set(entry) - GENERATED_KEYS)
            if extra:
                _fail(source, "%s.%s" % (key, extra[0]),
                      "unknown key for a generated sequence (known: %s)" % ", ".join(sorted(GENERATED_KEYS)))
            presets = presets if presets is not None else _presets(tools)
            if entry["preset"] not in presets:
                _fail(source, key + ".preset", "unknown preset %r (known: %s)" % (
                    entry["preset"], ", ".join(presets)))
            seed = _whole(source, key + ".seed", entry.get("seed", 1), 0)
            frames = _whole(source, key + ".frames", entry.get("frames", 0), 0)
            size = entry.get("size", "")
            if size and not re.match(r"^\d+x\d+$", str(size)):
                _fail(source, key + ".size", "expected WxH, e.g. 320x240")
            detector = entry.get("detector", "")  # "": the preset's own
            if detector and detector not in DETECTORS:
                _fail(source, key + ".detector", "expected %s, got %r" % (
                    " or ".join(DETECTORS), detector))
            sequence = {"name": entry.get("name", "%s_s%d" % (entry["preset"], seed)),
                        "generated": True, "preset": entry["preset"], "seed": seed,
                        "frames": frames, "size": str(size), "detector": detector,
                        "format": "tum", "max_frames": 0, "detect": None,
                        "snapshots": _snapshots(source, key + ".snapshots",
                                                entry.get("snapshots", False))}
        else:
            extra = sorted(set(entry) - USER_KEYS)
            if extra:
                _fail(source, "%s.%s" % (key, extra[0]),
                      "unknown key for a sequence folder (known: %s)" % ", ".join(sorted(USER_KEYS)))
            path = _path(source, key + ".path", base, entry["path"], "dir")
            form = entry.get("format", "tum")
            if form not in ("tum", "euroc"):
                _fail(source, key + ".format", "expected tum or euroc, got %r" % form)
            if "settings" not in entry:
                _fail(source, key + ".settings", "required for a sequence folder (its camera)")
            groundtruth = entry.get("groundtruth")
            if groundtruth is None and os.path.isfile(os.path.join(path, "groundtruth.txt")):
                groundtruth = "groundtruth.txt"
            sequence = {
                "name": entry.get("name", re.sub(r"[^A-Za-z0-9_.-]", "_", os.path.basename(path))),
                "generated": False,
                "path": path, "format": form,
                "settings": _path(source, key + ".settings", base, entry["settings"], "file"),
                "groundtruth": _path(source, key + ".groundtruth", path, groundtruth, "file")
                if groundtruth else None,
                "detections": _path(source, key + ".detections", base, entry["detections"],
                                    "dir", path) if "detections" in entry else None,
                "detect": _detect(source, key + ".detect", base, entry.get("detect", False)),
                "snapshots": _snapshots(source, key + ".snapshots", entry.get("snapshots", False)),
                "objects_gt": _path(source, key + ".objects_gt", base, entry["objects_gt"],
                                    "file", path) if "objects_gt" in entry else None,
                "max_frames": _whole(source, key + ".max_frames", entry.get("max_frames", 0), 0)}
            if sequence["detect"] is not None and sequence["detections"] is not None:
                _fail(source, key + ".detect", "give either detect: (ocg_detect makes the "
                      "detections) or detections: (your folder), not both")
            if sequence["detect"] is not None and form != "tum":
                _fail(source, key + ".detect", "ocg_detect reads a TUM frame list (rgb.txt); "
                      "detect a EuRoC folder with ocg_detect --images FOLDER and give "
                      "detections:")
            sequence["first_image"] = _first_image(source, key, path, form)
        # Settings keys of this sequence alone, on top of its settings file (the variants'
        # keys go on top of them): what a real sequence's camera or scene needs.
        own = entry.get("set", {})
        if not isinstance(own, dict):
            _fail(source, key + ".set", "expected {settings key: value}")
        sequence["set"] = flatten(own, "", {})
        for setting, value in sequence["set"].items():
            if setting == "System.sequential":
                _fail(source, "%s.set.%s" % (key, setting), "set by executions: (sequential, "
                      "threaded)")
        if not NAME.match(str(sequence["name"])):
            _fail(source, key + ".name", "use letters, digits, '_', '-' and '.' only")
        if sequence["name"] in names:
            _fail(source, key + ".name", "%r is used twice" % sequence["name"])
        names.add(sequence["name"])
        sequences.append(sequence)

    modes = raw.get("modes", ["paper"])
    if not isinstance(modes, list) or not modes:
        _fail(source, "modes", "expected a non-empty list, e.g. [paper, improved]")
    for index, mode in enumerate(modes):
        if not isinstance(mode, str) or not _mode_ok(mode):
            _fail(source, "modes[%d]" % index, "unknown OCG mode %r (paper, improved, off, "
                  "visibility, or fallback/in_image/guard joined with '+')" % (mode,))
    if len(set(modes)) != len(modes):
        _fail(source, "modes", "a mode is listed twice")

    variants = raw.get("variants", {"default": {}})
    if not isinstance(variants, dict) or not variants:
        _fail(source, "variants", "expected a mapping: variant name -> {settings key: value}")
    for name, overrides in variants.items():
        if not NAME.match(str(name)):
            _fail(source, "variants.%s" % name, "use letters, digits, '_', '-' and '.' only")
        if overrides is None:
            variants[name] = overrides = {}
        if not isinstance(overrides, dict):
            _fail(source, "variants.%s" % name, "expected {settings key: value}, e.g. "
                  "{LoopClosing.enabled: false}")
        # Nested keys as the settings files allow them: {LoopClosing: {enabled: false}}.
        variants[name] = overrides = flatten(overrides, "", {})
        for setting, value in overrides.items():
            if not isinstance(setting, str) or "." not in setting:
                _fail(source, "variants.%s.%s" % (name, setting),
                      "expected a dotted settings key such as OCG.tau_doubt")
            if setting == "System.sequential":
                _fail(source, "variants.%s.%s" % (name, setting),
                      "set by executions: (sequential, threaded), not by a variant")
            if isinstance(value, dict) or (isinstance(value, list) and any(
                    isinstance(item, (dict, list)) for item in value)):
                _fail(source, "variants.%s.%s" % (name, setting),
                      "expected a value or a list of values")

    executions = raw.get("executions", ["sequential"])
    if not isinstance(executions, list) or not executions or \
            any(e not in EXECUTIONS for e in executions):
        _fail(source, "executions", "expected a list of sequential and/or threaded")
    repeats = _whole(source, "repeats", raw.get("repeats", 3), 1)
    realtime = raw.get("realtime", True)
    if not isinstance(realtime, bool):
        _fail(source, "realtime", "expected true or false")
    max_dt = raw.get("max_dt", 0.02)
    if isinstance(max_dt, bool) or not isinstance(max_dt, (int, float)) or max_dt <= 0:
        _fail(source, "max_dt", "expected a positive number of seconds")

    if out_override:
        out = os.path.abspath(out_override)
    elif "out" in raw:
        out = _path(source, "out", base, raw["out"], None)
    else:
        _fail(source, "out", "required: the folder of the runs, tables and plots")

    _check_settings(source, tools, sequences, variants)

    runs = []
    for sequence in sequences:
        has_objects = sequence["generated"] or sequence["detections"] is not None or \
            sequence["detect"] is not None
        for variant in variants:
            for mode in (modes if has_objects else ["slam"]):
                for execution in executions:
                    count = repeats if execution == "threaded" else 1
                    for repeat in range(1, count + 1):
                        runs.append("%s/%s/%s/%s-%d" % (sequence["name"], variant, mode,
                                                          execution, repeat))
    return {"config": os.path.abspath(config_path), "out": out, "tools": tools,
            "sequences": sequences, "modes": modes, "variants": variants,
            "executions": executions, "repeats": repeats, "realtime": realtime,
            "max_dt": float(max_dt), "runs": runs}


def write_resolved(batch, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    temporary = path + ".tmp"
    with open(temporary, "w") as handle:
        json.dump(batch, handle, indent=1)
    os.replace(temporary, path)
