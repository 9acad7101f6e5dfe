#!/usr/bin/env bash
# End to end, map files and sessions (docs/sessions.md): the smoke sequence's first 140
# frames are session 0, saved with --save-map; frames 141-300 are session 1, run with
# --load-map (it starts where session 0 stopped and comes back to session 0's start).
# Checks: session 1 relocalizes within 30 frames, never resets, adds keyframes to the
# loaded ones, closes a loop onto them, and both sessions' keyframes fit the ground
# truth under one Sim(3) within 2 cm (one coordinate frame); the object map holds each
# static object once, none deleted, with the sessions that saw it. A scene the map does
# not hold never relocalizes and makes no map of its own; a foreign or truncated map
# file fails at startup, naming the file.
#   session_test.sh <folder with the tool binaries> [the smoke300 sequence, else generated here]
set -euo pipefail
BIN=$1
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAILED: $*"; exit 1; }
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

source "$(dirname "$0")/smoke300.sh"
smoke300 "$BIN" "${2:-}"
# Each session's folder lists its frames; images, detections and ground truth are shared.
for session in 0 1; do
  mkdir -p "$WORK/s$session"
  ln -s "$SMOKE/rgb" "$WORK/s$session/rgb"
done
grep -v '^#' "$SMOKE/rgb.txt" | sed -n '1,140p' >"$WORK/s0/rgb.txt"
grep -v '^#' "$SMOKE/rgb.txt" | sed -n '141,300p' >"$WORK/s1/rgb.txt"
run() {  # run <session folder> <out> [options...]
  local sequence=$1 out=$2
  shift 2
  "$BIN/ocg_slam" run --settings "$SMOKE/camera.yaml" --sequence "$sequence" \
    --detections "$SMOKE/detections" --snapshots none --out "$out" --log-level warn "$@"
}
run "$WORK/s0" "$WORK/r0" --save-map "$WORK/maps/a.ocgmap" >"$WORK/r0.log"
cat "$WORK/r0.log"
[ "$(head -c 17 "$WORK/maps/a.ocgmap")" = "OCG-SLAM map file" ] || fail "no map file written"
run "$WORK/s1" "$WORK/r1" --load-map "$WORK/maps/a.ocgmap" --save-map "$WORK/maps/b.ocgmap" >"$WORK/r1.log"
cat "$WORK/r1.log"

until=$(json "$WORK/r1/run.json" "d['session']['frames_until_relocalized']")
[ "$until" != never ] && [ "$until" -le 30 ] || fail "relocalized after $until frames (want within 30)"
[ "$(json "$WORK/r1/run.json" "d['session']['index']")" -eq 1 ] || fail "session index is not 1"
[ "$(json "$WORK/r1/run.json" "d['map_resets']")" -eq 0 ] || fail "the second session reset the map"
loaded=$(json "$WORK/r1/run.json" "d['session']['keyframes_loaded']")
keyframes=$(json "$WORK/r1/run.json" "d['keyframes']")
[ "$keyframes" -gt "$loaded" ] || fail "$keyframes keyframes after loading $loaded: none added"
old=$(awk '$1 < 1014.0' "$WORK/r1/KeyFrameTrajectory.txt" | wc -l)
new=$(awk '$1 >= 1014.0' "$WORK/r1/KeyFrameTrajectory.txt" | wc -l)
[ "$old" -ge 10 ] && [ "$new" -ge 10 ] || fail "the map holds $old keyframes of session 0, $new of session 1"
loops=$(json "$WORK/r1/run.json" "len(d['loop_closing']['loops'])")
[ "$loops" -ge 1 ] || fail "session 1 came back to session 0's start but closed no loop"
"$BIN/ocg_eval" ate --gt "$SMOKE/groundtruth.txt" --est "$WORK/r1/KeyFrameTrajectory.txt" --align sim3 >"$WORK/ate.txt"
cat "$WORK/ate.txt"
rmse=$(awk '$1 == "rmse" {print $2}' "$WORK/ate.txt")
awk -v r="$rmse" 'BEGIN { exit !(r < 0.02) }' || fail "both sessions' keyframes: ATE RMSE $rmse m under one Sim(3) (want < 0.02)"
echo "passed: relocalized after $until frame(s), $loaded + $((keyframes - loaded)) keyframes ($old of session 0, $new of session 1), $loops loop(s), ATE RMSE $rmse m over both sessions"

"$BIN/ocg_eval" objects --gt "$SMOKE/objects_gt.json" --run "$WORK/r1" \
  --groundtruth "$SMOKE/groundtruth.txt" --json >"$WORK/objects.json"
corr_s=$(json "$WORK/objects.json" "d['corr_s']")
redun_s=$(json "$WORK/objects.json" "d['redun_s']")
delet_s=$(json "$WORK/objects.json" "d['delet_s']")
[ "$corr_s" -ge 6 ] || fail "only $corr_s static objects mapped (want at least 6)"
[ "$redun_s" -le 1 ] || fail "$redun_s redundant objects (want at most 1): session 1 mapped them again"
[ "$delet_s" -eq 0 ] || fail "$delet_s static objects deleted"
both=$(json "$WORK/r1/objects.json" "sum(o['first_session'] == 0 and o['last_session'] == 1 for o in d['objects'])")
[ "$both" -ge 4 ] || fail "only $both objects seen in both sessions"
echo "passed: $corr_s static objects, $redun_s redundant, none deleted, $both seen in both sessions"

# The saved map of both sessions continues as session 2.
[ "$(json "$WORK/r1/run.json" "d['session']['map_saved']")" = "$WORK/maps/b.ocgmap" ] || fail "run.json does not name the saved map"

# A place the map does not hold (another layout): it keeps trying and makes no map.
"$BIN/ocg_synth" --preset smoke --seed 5 --frames 30 --out "$WORK/other" --keyframe-interval 0 --log-level warn >/dev/null
"$BIN/ocg_slam" run --settings "$SMOKE/camera.yaml" --sequence "$WORK/other" --snapshots none \
  --out "$WORK/r2" --load-map "$WORK/maps/b.ocgmap" --log-level warn >"$WORK/r2.log" 2>&1
until=$(json "$WORK/r2/run.json" "d['session']['frames_until_relocalized']")
[ "$until" = never ] || fail "relocalized in a scene the map does not hold (after $until frames)"
[ "$(json "$WORK/r2/run.json" "d['keyframes']")" -eq "$keyframes" ] || fail "keyframes were added without relocalizing"
[ "$(json "$WORK/r2/run.json" "d['map_resets']")" -eq 0 ] || fail "the map was reset"
grep -q "never relocalized" "$WORK/r2.log" || fail "the run did not say it never relocalized"
echo "passed: an unknown place never relocalizes, no map of its own"

# Foreign and truncated map files fail at startup, naming the file.
if "$BIN/ocg_slam" run --settings "$SMOKE/camera.yaml" --sequence "$WORK/s1" --out "$WORK/r3" \
  --load-map "$SMOKE/rgb.txt" >"$WORK/r3.log" 2>&1; then fail "a foreign map file was accepted"; fi
grep -q "'$SMOKE/rgb.txt' is not an OCG-SLAM map file" "$WORK/r3.log" || { cat "$WORK/r3.log"; fail "no clear error for a foreign file"; }
[ ! -e "$WORK/r3/run.json" ] || fail "a run went ahead with a foreign map file"
head -c 100000 "$WORK/maps/a.ocgmap" >"$WORK/maps/cut.ocgmap"
if "$BIN/ocg_slam" run --settings "$SMOKE/camera.yaml" --sequence "$WORK/s1" --out "$WORK/r4" \
  --load-map "$WORK/maps/cut.ocgmap" >"$WORK/r4.log" 2>&1; then fail "a truncated map file was accepted"; fi
grep -q "cut.ocgmap': truncated" "$WORK/r4.log" || { cat "$WORK/r4.log"; fail "no clear error for a truncated file"; }
echo "passed: foreign and truncated map files refused at startup"

# A --save-map that names a folder fails before any frame, naming the option.
if "$BIN/ocg_slam" run --settings "$SMOKE/camera.yaml" --sequence "$WORK/s1" --out "$WORK/r5" \
  --save-map "$WORK/maps" >"$WORK/r5.log" 2>&1; then fail "a folder was accepted as --save-map"; fi
grep -q -- "--save-map '$WORK/maps' is a folder" "$WORK/r5.log" || { cat "$WORK/r5.log"; fail "no clear error for a --save-map folder"; }
[ ! -e "$WORK/r5/run.json" ] || fail "a run went ahead with a folder as --save-map"
echo "passed: a folder as --save-map refused at startup"
