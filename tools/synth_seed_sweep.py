#!/usr/bin/env python3
"""synth_seed_sweep: does ocg_synth make a valid scene for every preset and seed, and the
same scene as another build?

Usage:
  tools/synth_seed_sweep.py OCG_SYNTH OUT [--presets P,...] [--seeds 1-20,31]
                            [--look realistic] [--detector realistic] [--baseline OCG_SYNTH]

For each seed and preset, OCG_SYNTH writes the scene into OUT/<preset>_s<seed>/ with one
frame and no images (`--frames 1 --detections-only`): the changes are scheduled for the
whole sequence all the same, and the generator refuses a scene whose changes would happen
in view, so a written scene is a valid one. Printed per scene: `ok` with the SHA-256 of
scene.yaml and objects_gt.json, or `refused` with ocg_synth's last line. With --baseline,
the same scene is made by that binary too (into OUT/baseline/), and a scene both accept
must be byte-identical (`identical` or `DIFFERENT`); a scene only the baseline refuses is
`newly accepted` (`baseline refused too` when both refuse it). Exit status 1 when a scene
is refused by OCG_SYNTH or differs.

A scene takes 10-70 s on a shared 2-core machine (the scheduling renders the visibility
of every change at every third frame): run it under `nice`, in the background.
"""
import argparse
import hashlib
import os
import subprocess
import sys

PRESETS = ["smoke", "straight_1", "straight_2", "round_1", "round_2"]  # the ones with changes
COMPARED = ["scene.yaml", "objects_gt.json"]


def parse_seeds(text):
    seeds = []
    for part in text.split(","):
        low, _, high = part.partition("-")
        seeds += list(range(int(low), int(high or low) + 1))
    return seeds


def make(binary, preset, seed, folder, extra):
    command = [binary, "--preset", preset, "--seed", str(seed), "--out", folder, "--frames", "1",
               "--detections-only", "--overwrite"] + extra
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        lines = (result.stderr or result.stdout).strip().splitlines()
        return None, lines[-1] if lines else "exit %d" % result.returncode
    digest = hashlib.sha256()
    for name in COMPARED:
        with open(os.path.join(folder, name), "rb") as handle:
            digest.update(handle.read())
    return digest.hexdigest(), ""


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0].split(": ", 1)[1])
    parser.add_argument("ocg_synth")
    parser.add_argument("out")
    parser.add_argument("--presets", default=",".join(PRESETS))
    parser.add_argument("--seeds", default="1-20")
    parser.add_argument("--look", default="realistic")
    parser.add_argument("--detector", default="realistic")
    parser.add_argument("--baseline", help="another ocg_synth: accepted scenes must be identical")
    args = parser.parse_args()
    extra = ["--look", args.look, "--detector", args.detector]
    failed = 0
    for seed in parse_seeds(args.seeds):
        for preset in args.presets.split(","):
            name = "%s_s%d" % (preset, seed)
            digest, error = make(args.ocg_synth, preset, seed, os.path.join(args.out, name), extra)
            line = "%-16s %s" % (name, "ok %s" % digest[:16] if digest else "refused: " + error)
            failed += digest is None
            if args.baseline:
                before, _ = make(args.baseline, preset, seed,
                                 os.path.join(args.out, "baseline", name), extra)
                if before is None:
                    line += "  (baseline refused%s)" % (" too" if digest is None else
                                                        ": newly accepted")
                elif digest == before:
                    line += "  identical"
                else:
                    line += "  DIFFERENT from the baseline"
                    failed += 1
            print(line, flush=True)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
