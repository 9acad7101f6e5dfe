"""One run's settings file: the sequence's settings (ours or ORB-SLAM2's), flattened to
dotted keys (the settings loader reads "A.b: v" as "A: {b: v}", and a key set twice is
an error, so overrides cannot simply be appended), the variant's keys and
System.sequential on top.

Usage: settings_variant.py BASE.yaml OUT.yaml EXECUTION 'JSON overrides'
"""
import json
import os
import sys

import yaml


def flatten(value, prefix, out):
    if isinstance(value, dict):
        for key, item in value.items():
            flatten(item, "%s.%s" % (prefix, key) if prefix else str(key), out)
    else:
        out[prefix] = value
    return out


def read_settings(path):
    with open(path) as handle:
        text = handle.read()
    # ORB-SLAM2's files are OpenCV YAML: a "%YAML:1.0" directive PyYAML does not take.
    if text.startswith("%YAML:1.0"):
        text = text.split("\n", 1)[1] if "\n" in text else ""
    if "!!opencv-matrix" in text:
        sys.exit("%s: OpenCV matrices (!!opencv-matrix) are not supported in a batch's "
                 "settings; write the values as plain keys" % path)
    return flatten(yaml.safe_load(text) or {}, "", {})


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    base, out, execution, overrides = sys.argv[1:]
    values = read_settings(base)
    values.update(json.loads(overrides))
    values["System.sequential"] = execution == "sequential"
    temporary = out + ".tmp"
    with open(temporary, "w") as handle:
        handle.write("# Made by the batch from %s (docs/batch.md)\n" % base)
        yaml.safe_dump(values, handle, default_flow_style=False, sort_keys=False)
    os.replace(temporary, out)


if __name__ == "__main__":
    main()
