#!/usr/bin/env bash
# The soak's half-minute version (tools/soak.sh): the smoke preset's first 120 frames
# played forward and back, threaded with detections, stopped by SIGINT after 30 s.
# Checks: the CSV holds a sample every 2 s with growing frame counts, the plot is
# written, the stopped run's outputs and map are whole and marked interrupted.
#   soak_smoke_test.sh <tools source folder> <folder with the tool binaries>
set -euo pipefail
TOOLS=$1
BIN=$2
source "$(dirname "$0")/check_helpers.sh"
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

check "the soak runs and reports" bash "$TOOLS/soak.sh" 0.5 --preset smoke --frames 120 --max-fps 400 \
  --sample-seconds 2 --out "$WORK/soak" --bin "$BIN"
cat "$WORK/out"
output_has "the soak measures the growth after the first pass" "after the first pass"
rows=$(($(wc -l <"$WORK/soak/soak.csv") - 1))
check "about one sample every 2 s ($rows)" test "$rows" -ge 8
check "frames grow from sample to sample" python3 - "$WORK/soak/soak.csv" <<'PY'
import csv, sys
frames = [float(row["frame"]) for row in csv.DictReader(open(sys.argv[1]))]
assert all(b > a for a, b in zip(frames, frames[1:])), frames
PY
check "the plot is written" grep -q "<polyline" "$WORK/soak/soak.svg"
check "the stopped run says interrupted" test "$(json "$WORK/soak/run/run.json" "d['interrupted']")" = True
check "the stopped run's map is written" test -s "$WORK/soak/soak.ocgmap"
# run.json's series: a sample every 10 s (whatever --sample-seconds), the end's replacing
# the one of its 10 s: at 0, 10 and about 29 s.
check "run.json keeps a short progress series" \
  test "$(json "$WORK/soak/run/run.json" "len(d['progress'])")" -ge 3
report_and_exit
