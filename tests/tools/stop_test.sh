#!/usr/bin/env bash
# End to end, a run stopped by a signal (docs/robustness.md, "Stopping a run"): SIGINT or
# SIGTERM in the middle of `ocg_slam run --detections --save-map` stops it after the frame
# in hand; every output and the map are then written whole, run.json says
# "interrupted": true, the exit code is 128 + the signal, and the map continues in a
# later session. A second signal exits at once. A run that never initializes writes no
# map (an empty one), but all its other outputs.
#   stop_test.sh <folder with the tool binaries> [the smoke300 sequence, else generated here]
set -euo pipefail
BIN=$1
source "$(dirname "$0")/check_helpers.sh"
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

source "$(dirname "$0")/smoke300.sh"
smoke300 "$BIN" "${2:-}"

# Starts a run in the background, logging its progress every second; waits until it has
# logged progress twice (it is then in the middle of its frames); PID in $pid.
start_run() {  # start_run <out> [options...]
  local out=$1
  shift
  "$BIN/ocg_slam" run --settings "$SMOKE/camera.yaml" --sequence "$SMOKE" \
    --detections "$SMOKE/detections" --snapshots none --out "$out" \
    --progress-seconds 1 "$@" >"$out.log" 2>&1 &
  pid=$!
  for _ in $(seq 600); do
    [ "$(grep -c '] progress: ' "$out.log" 2>/dev/null)" -ge 2 ] && return 0
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  cat "$out.log"
  echo "the run ended or logged no progress before the signal"
  return 1
}
finish_run() {  # finish_run <out>: waits for the run; its exit code in $code
  code=0
  wait "$pid" || code=$?
  cat "$1.log"
}

for signal in INT TERM; do
  out="$WORK/$signal"
  start_run "$out" --save-map "$WORK/$signal.ocgmap"
  kill -s "$signal" "$pid"
  finish_run "$out"
  expected=$((128 + $(kill -l "$signal")))
  check "SIG$signal: exit code $expected (got $code)" test "$code" -eq "$expected"
  check "SIG$signal: run.json says interrupted" test "$(json "$out/run.json" "d['interrupted']")" = True
  frames=$(json "$out/run.json" "d['frames']")
  check "SIG$signal: stopped in the middle ($frames of 300 frames)" test "$frames" -gt 0 -a "$frames" -lt 300
  check "SIG$signal: the log says where it stopped" \
    grep -q "stopped by a signal after $frames of 300 frames" "$out.log"
  # Every output whole: the trajectories hold every keyframe and tracked frame, the
  # object files parse, the map's payload is as long as its header says.
  keyframes=$(json "$out/run.json" "d['keyframes']")
  tracked=$(json "$out/run.json" "d['frames_tracked']")
  check "SIG$signal: $keyframes keyframes in KeyFrameTrajectory.txt" \
    test "$(grep -vc '^#' "$out/KeyFrameTrajectory.txt")" -eq "$keyframes" -a "$keyframes" -gt 2
  check "SIG$signal: $tracked tracked frames in CameraTrajectory.txt" \
    test "$(grep -vc '^#' "$out/CameraTrajectory.txt")" -ge "$tracked"
  for file in objects.json changes.json ocg.json; do
    check "SIG$signal: $file parses" python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$out/$file"
  done
  check "SIG$signal: map points written" test -s "$out/map_points.ply"
  check "SIG$signal: the progress series ends at the last frame" \
    test "$(json "$out/run.json" "d['progress'][-1]['frames']")" -eq "$frames"
  map="$WORK/$signal.ocgmap"
  check "SIG$signal: the map file's payload is whole" python3 - "$map" <<'EOF'
import sys
data = open(sys.argv[1], "rb").read()
lines = data.split(b"\n", 4)
assert lines[0] == b"OCG-SLAM map file", lines[0]
size = int(lines[3].split()[1])
assert len(lines[4]) == size, (len(lines[4]), size)
EOF
done

# The map of the stopped run continues: the next session relocalizes in it.
"$BIN/ocg_slam" run --settings "$SMOKE/camera.yaml" --sequence "$SMOKE" \
  --detections "$SMOKE/detections" --snapshots none --out "$WORK/next" --max-frames 10 \
  --load-map "$WORK/INT.ocgmap" --log-level warn >"$WORK/out" 2>&1 || failure "the stopped run's map does not load"
output_has "the next session runs in the stopped run's map" "session 1 of the map"
check "the next session relocalized" test "$(json "$WORK/next/run.json" "d['session']['frames_until_relocalized']")" != never

# A second signal exits at once, writing nothing more. (Sent once the first was taken:
# two signals sent together may arrive as one.)
start_run "$WORK/twice"
kill -s INT "$pid"
for _ in $(seq 500); do
  grep -q "stopping after the frame in hand" "$WORK/twice.log" && break
  sleep 0.01
done
kill -s INT "$pid"
finish_run "$WORK/twice"
check "a second signal exits with 130 (got $code)" test "$code" -eq 130
check "the second signal says it exits at once" grep -q "second signal: exiting at once" "$WORK/twice.log"

# A run that never initializes (a still camera: the first frame over and over) writes
# its outputs but refuses an empty map, saying so.
mkdir -p "$WORK/still"
ln -s "$SMOKE/rgb" "$WORK/still/rgb"
# awk reads the whole list: `grep | head -1` under pipefail fails at random, when head
# exits before grep has written its last block (SIGPIPE, exit 141).
first=$(awk '!/^#/ && !found { print $2; found = 1 }' "$SMOKE/rgb.txt")
for i in $(seq 0 19); do printf '%d.%06d %s\n' 100 $((i * 33333)) "$first"; done >"$WORK/still/rgb.txt"
fails_with "an empty map is refused" "the map is empty" \
  "$BIN/ocg_slam" run --settings "$SMOKE/camera.yaml" --sequence "$WORK/still" \
  --snapshots none --out "$WORK/still_out" --save-map "$WORK/still.ocgmap"
check "no map file written for an empty map" test ! -e "$WORK/still.ocgmap"
check "the never-initialized run's outputs are written" test -s "$WORK/still_out/run.json"

report_and_exit
