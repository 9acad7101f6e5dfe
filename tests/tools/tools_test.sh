#!/usr/bin/env bash
# End-to-end checks of the command-line tools, run by CTest:
#   tools_test.sh <folder with the tool binaries> <project source folder>
set -u
BIN=$1
SRC=$2
source "$(dirname "${BASH_SOURCE[0]}")/check_helpers.sh"

for tool in ocg_eval ocg_replay ocg_convert_detections ocg_synth ocg_vocab ocg_slam ocg_diff ocg_render; do
  check "$tool --help" "$BIN/$tool" --help
done

# ocg_replay on the shipped example: the cup (object 1) is removed at keyframe 7.
check "ocg_replay example" "$BIN/ocg_replay" --input "$SRC/tests/data/ocg_example.jsonl" --out "$WORK/replay"
check "states.jsonl has one line per keyframe" test "$(wc -l <"$WORK/replay/states.jsonl")" -eq 9
check "changes.json names the moved cup" grep -q '"object_id": 1' "$WORK/replay/changes.json"
check "removed at keyframe 7" grep -q '"keyframe": 7' "$WORK/replay/changes.json"
check "keyframe 7 line lists the removal" grep -q '"keyframe":7,.*"removed":\[1\]' "$WORK/replay/states.jsonl"
check "ocg.json written" grep -q '"format": "ocg-graph"' "$WORK/replay/ocg.json"
check "second run" "$BIN/ocg_replay" --input "$SRC/tests/data/ocg_example.jsonl" --out "$WORK/replay2"
check "identical outputs for identical inputs" diff -r "$WORK/replay" "$WORK/replay2"

# An object removed and seen again re-enters with its last centroid (SPEC 3.1) and can be
# judged again: object 1 (centroid (0, 0, 2), sent once at keyframe 0) is removed at
# keyframe 5, re-enters at 6, and at keyframe 8 is suspicious with doubt 30 (rate 1, in view).
seen=('[1, 2]' '[2]' '[3]' '[2]' '[2]' '[3]' '[1, 2]' '[3]' '[2]')
for k in "${!seen[@]}"; do
  centroids='{}'
  [ "$k" -eq 0 ] && centroids='{"1": [0, 0, 2]}'
  echo "{\"keyframe\": $k, \"timestamp\": $k, \"T_cw\": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], \"camera\": {\"fx\": 500, \"fy\": 500, \"cx\": 320, \"cy\": 240, \"width\": 640, \"height\": 480}, \"observed\": ${seen[$k]}, \"centroids\": $centroids}"
done >"$WORK/reentry.jsonl"
check "ocg_replay --mode paper on a re-entry" "$BIN/ocg_replay" --input "$WORK/reentry.jsonl" --out "$WORK/reentry" --mode paper
check "object 1 removed at keyframe 5" grep -q '"keyframe":5,.*"removed":\[1\]' "$WORK/reentry/states.jsonl"
check "re-entered at keyframe 6 in state 1" grep -q '"keyframe":6,"objects":\[{"active_edge_rate":[0-9.]*,"doubt":0[.0]*,"id":1,"state":1}' "$WORK/reentry/states.jsonl"
check "keyframe 8: suspicious again with doubt 30" grep -q '"keyframe":8,"objects":\[{"active_edge_rate":1[.0]*,"doubt":30[.0]*,"id":1,"state":4}' "$WORK/reentry/states.jsonl"

# Malformed input: an error naming the line, and nothing written.
{ head -n 3 "$SRC/tests/data/ocg_example.jsonl"; echo '{"keyframe": 3, "T_cw": [1, 2]}'; } >"$WORK/bad.jsonl"
fails_with "ocg_replay names the bad line" "bad.jsonl:4" "$BIN/ocg_replay" --input "$WORK/bad.jsonl" --out "$WORK/bad_out"
check "nothing written on failure" test ! -e "$WORK/bad_out"
fails_with "ocg_replay rejects an unknown mode" "OCG.mode" "$BIN/ocg_replay" --input "$SRC/tests/data/ocg_example.jsonl" --out "$WORK/x" --mode nonsense

# ocg_eval ate: an estimate that is the ground truth scaled by 3 and shifted.
awk '{ printf "%s %.9f %.9f %.9f 0 0 0 1\n", $1, $2, $3, $4 }' >"$WORK/gt.txt" <<'DATA'
1.00 0.0 0.0 0.0
1.10 1.0 0.0 0.0
1.20 1.0 1.0 0.0
1.30 0.0 1.0 0.5
1.40 0.5 0.5 1.0
DATA
awk '{ printf "%.3f %.9f %.9f %.9f 0 0 0 1\n", $1 + 0.005, 3 * $2 + 1, 3 * $3 - 2, 3 * $4 }' "$WORK/gt.txt" >"$WORK/est.txt"
check "ocg_eval ate runs" "$BIN/ocg_eval" ate --gt "$WORK/gt.txt" --est "$WORK/est.txt"
"$BIN/ocg_eval" ate --gt "$WORK/gt.txt" --est "$WORK/est.txt" >"$WORK/ate.txt"
check "ate scale is 1/3" grep -q "^scale   0.333333" "$WORK/ate.txt"
check "ate rmse is 0" grep -q "^rmse    0.000000" "$WORK/ate.txt"
check "ate --json" "$BIN/ocg_eval" ate --gt "$WORK/gt.txt" --est "$WORK/est.txt" --json
fails_with "ate with disjoint times" "time base" "$BIN/ocg_eval" ate --gt "$WORK/gt.txt" --est "$WORK/est.txt" --max-dt 0.001
check "ocg_eval rpe runs" "$BIN/ocg_eval" rpe --gt "$WORK/gt.txt" --est "$WORK/est.txt"
fails_with "missing file is named" "nope.txt" "$BIN/ocg_eval" ate --gt "$WORK/nope.txt" --est "$WORK/est.txt"

# KITTI poses (12 numbers a line, no time), recognised by content. Two KITTI files pair
# row by row; a KITTI file against a TUM one takes its rows' times from --times.
awk '!/^#/ { print $1 }' "$WORK/gt.txt" >"$WORK/times.txt"
check "ocg_eval convert TUM -> KITTI" "$BIN/ocg_eval" convert --in "$WORK/gt.txt" --to kitti --out "$WORK/gt_kitti.txt"
check "... 12 numbers a line" test "$(awk '{ print NF }' "$WORK/gt_kitti.txt" | sort -u)" = 12
check "... back to TUM with the times" "$BIN/ocg_eval" convert --in "$WORK/gt_kitti.txt" --to tum --times "$WORK/times.txt" --out "$WORK/gt_again.txt"
"$BIN/ocg_eval" ate --gt "$WORK/gt_again.txt" --est "$WORK/gt.txt" --align none >"$WORK/out" 2>&1
output_has "... the same poses" "rmse    0.000000"
check "ocg_eval ate KITTI against TUM with --times" "$BIN/ocg_eval" ate --gt "$WORK/gt_kitti.txt" --est "$WORK/est.txt" --times "$WORK/times.txt"
output_has "... scale 1/3 as from the TUM file" "scale   0.333333"
output_has "... rmse 0" "rmse    0.000000"
fails_with "KITTI against TUM without --times" "give the KITTI rows' times with --times" "$BIN/ocg_eval" ate --gt "$WORK/gt_kitti.txt" --est "$WORK/est.txt"
check "est to KITTI" "$BIN/ocg_eval" convert --in "$WORK/est.txt" --to kitti --out "$WORK/est_kitti.txt"
check "ocg_eval ate on two KITTI files (row by row)" "$BIN/ocg_eval" ate --gt "$WORK/gt_kitti.txt" --est "$WORK/est_kitti.txt"
output_has "... rmse 0" "rmse    0.000000"
head -n 3 "$WORK/est_kitti.txt" >"$WORK/est_kitti_short.txt"
fails_with "two KITTI files of other lengths" "holds 5 poses and '$WORK/est_kitti_short.txt' 3" "$BIN/ocg_eval" ate --gt "$WORK/gt_kitti.txt" --est "$WORK/est_kitti_short.txt"
# One row per frame of times.txt: a frame without a pose is refused, naming it.
{ cat "$WORK/times.txt"; echo 1.50; } >"$WORK/times_more.txt"
fails_with "convert --to kitti --times with a frame without a pose" "1 of the 6 frames of '$WORK/times_more.txt' have no pose" \
  "$BIN/ocg_eval" convert --in "$WORK/gt.txt" --to kitti --times "$WORK/times_more.txt" --out "$WORK/x.txt"
check "... nothing written" test ! -e "$WORK/x.txt"
DATA="$SRC/../shared/data/kitti_07_first160"
if [ -d "$DATA" ]; then
  # The real KITTI ground truth against its TUM conversion: the same poses.
  check "real KITTI poses against their TUM conversion" "$BIN/ocg_eval" ate --gt "$DATA/poses_kitti.txt" --est "$DATA/groundtruth.txt" --times "$DATA/times.txt" --align none
  output_has "... 160 pairs" "pairs   160"
  output_has "... rmse 0" "rmse    0.000000"
  # A KITTI odometry folder read directly (image_0/, times.txt, calib.txt).
  check "ocg_slam run --format kitti" "$BIN/ocg_slam" run --format kitti --sequence "$DATA" --settings "$DATA/orbslam2_KITTI04-12.yaml" --max-frames 3 --snapshots none --out "$WORK/kitti_run"
  output_has "... 3 frames of the folder" "3 frames of $DATA"
fi

# ocg_convert_detections: EAO folder -> JSON -> EAO folder gives the same detections.
mkdir -p "$WORK/eao"
printf '56 16 256 220 215 0.909657\n39 289 18 23 92 0.767674\n' >"$WORK/eao/1341847980.722988.txt"
printf '41 1 2 3 4 0.5' >"$WORK/eao/1341847981.000000.txt"
check "EAO to JSON" "$BIN/ocg_convert_detections" --from "$WORK/eao" --to "$WORK/d.json"
check "JSON to EAO" "$BIN/ocg_convert_detections" --from "$WORK/d.json" --to "$WORK/eao2"
check "round trip identical" diff "$WORK/eao/1341847980.722988.txt" "$WORK/eao2/1341847980.722988.txt"
check "file_name carries prefix" grep -q '"rgb/1341847980.722988.png"' "$WORK/d.json"
printf '56 16 256 220\n' >"$WORK/eao/1341847982.000000.txt"
fails_with "malformed detection names file and line" "1341847982.000000.txt:1" "$BIN/ocg_convert_detections" --from "$WORK/eao" --to "$WORK/d2.json"
check "lenient skips it" "$BIN/ocg_convert_detections" --from "$WORK/eao" --to "$WORK/d3.json" --lenient

# ocg_vocab: train on a few rendered frames, describe, convert to ORB-SLAM2 text and back.
check "render frames to train on" "$BIN/ocg_synth" --preset smoke --frames 6 --out "$WORK/frames" --keyframe-interval 0 --log-level warn
check "ocg_vocab train" bash -c "'$BIN/ocg_vocab' train --images '$WORK/frames/rgb.txt' --images '$WORK/frames/rgb' --k 4 --L 3 --out '$WORK/v.ocgvoc' >'$WORK/train.log'"
check "trained from 12 images" grep -q "from 12 images" "$WORK/train.log"
check "ocg_vocab info" bash -c "'$BIN/ocg_vocab' info '$WORK/v.ocgvoc' >'$WORK/info.log'"
check "info says k and L" grep -q "k = 4, L = 3" "$WORK/info.log"
check "to ORB-SLAM2 text" "$BIN/ocg_vocab" convert --in "$WORK/v.ocgvoc" --out "$WORK/v.txt" --text
check "text header" grep -qx "4 3 0 0" "$WORK/v.txt"
check "ORBvoc text to binary" "$BIN/ocg_vocab" convert --orbvoc "$WORK/v.txt" --out "$WORK/v2.ocgvoc"
check "binary round trip identical" cmp "$WORK/v.ocgvoc" "$WORK/v2.ocgvoc"
check "ocg_vocab pairs" bash -c "'$BIN/ocg_vocab' pairs --vocabulary '$WORK/v.ocgvoc' --vocabulary '$WORK/v2.ocgvoc' --images '$WORK/frames/rgb.txt' --near 1 --far 3 --log-level warn >'$WORK/pairs.log'"
# 6 frames: 5 pairs 1 apart, 3 + 2 + 1 pairs at least 3 apart; one row per vocabulary.
check "pairs counted, a row per vocabulary" test "$(grep -c '| 5 / 6 |' "$WORK/pairs.log")" = 2
fails_with "pairs refuses far inside near" "far (1) must exceed near (1)" "$BIN/ocg_vocab" pairs --vocabulary "$WORK/v.ocgvoc" --images "$WORK/frames/rgb.txt" --near 1 --far 1
printf '4 3 0 0\n0 1 7\n' >"$WORK/broken.txt"
fails_with "broken vocabulary names file and line" "broken.txt:2: missing descriptor byte" "$BIN/ocg_vocab" convert --orbvoc "$WORK/broken.txt" --out "$WORK/never.ocgvoc"
check "nothing written on failure" test ! -e "$WORK/never.ocgvoc"
printf 'rgb/missing.png\n' >"$WORK/list.txt"
fails_with "missing image named" "missing.png" "$BIN/ocg_vocab" train --images "$WORK/list.txt" --out "$WORK/never.ocgvoc"

# ocg_slam: errors name what is wrong.
mkdir -p "$WORK/empty_sequence"
fails_with "ocg_slam names the missing rgb.txt" "empty_sequence/rgb.txt' is missing" "$BIN/ocg_slam" run --settings "$SRC/config/TUM1.yaml" --sequence "$WORK/empty_sequence" --out "$WORK/slam"
printf 'OCG:\n  mode: paper\n' >"$WORK/no_camera.yaml"
fails_with "ocg_slam run names the missing camera keys" "no_camera.yaml: camera keys missing: this command needs Camera.fx, Camera.fy, Camera.cx, Camera.cy" "$BIN/ocg_slam" run --settings "$WORK/no_camera.yaml" --sequence "$WORK/frames" --out "$WORK/never_slam"
check "nothing written without a camera" test ! -e "$WORK/never_slam"
fails_with "ocg_slam names a missing vocabulary" "vocabulary: cannot read '$WORK/none.ocgvoc': it does not exist" "$BIN/ocg_slam" run --settings "$SRC/config/TUM1.yaml" --sequence "$WORK/frames" --out "$WORK/slam" --vocabulary "$WORK/none.ocgvoc"
check "ocg_slam on six frames" "$BIN/ocg_slam" run --settings "$WORK/frames/camera.yaml" --sequence "$WORK/frames" --out "$WORK/slam" --log-level warn
check "run.json written" grep -q '"frames": 6' "$WORK/slam/run.json"

# Pose-given object mapping and the object metrics, on a small generated sequence.
check "render a small sequence" "$BIN/ocg_synth" --preset smoke --frames 300 --size 320x240 --out "$WORK/objseq" --keyframe-interval 0 --log-level warn
objects_run() {  # objects_run OUT SETTINGS [extra args...]
  local out=$1 settings=$2
  shift 2
  "$BIN/ocg_slam" objects --trajectory "$WORK/objseq/groundtruth.txt" --detections "$WORK/objseq/detections" --frames "$WORK/objseq/rgb.txt" --settings "$settings" --out "$out" --log-level warn "$@"
}
check "ocg_slam objects (pose-given)" objects_run "$WORK/objects" "$WORK/objseq/camera.yaml"
for file in objects.json changes.json ocg.json ocg_observations.jsonl run.json; do
  check "objects run wrote $file" test -s "$WORK/objects/$file"
done
# A pose-given run is looked at like a SLAM run (issue 32, points 5 and 9): the given
# trajectory, snapshots with the last frame's image under its detections, ocg_render on its
# folder, the object map as a mesh.
check "objects run wrote the given trajectory" test "$(wc -l <"$WORK/objects/CameraTrajectory.txt")" -eq 300
for view in follow top three_quarter objects frame; do
  check "objects run wrote final_$view.png" test -s "$WORK/objects/snapshots/final_$view.png"
done
check "ocg_render draws a pose-given run and writes its meshes" "$BIN/ocg_render" --run "$WORK/objects" --out "$WORK/objects_render" --views top --mesh "$WORK/objects_render/map.ply" --mesh "$WORK/objects_render/map.obj" --log-level warn
check "ocg_render wrote map_top.png" test -s "$WORK/objects_render/map_top.png"
live=$(python3 -c "import json; print(len(json.load(open('$WORK/objects/objects.json'))['objects']))")
check "the PLY mesh has 12 triangles per live object" grep -q "^element face $((12 * live))\$" "$WORK/objects_render/map.ply"
check "the OBJ mesh has 12 faces per live object" test "$(grep -c '^f ' "$WORK/objects_render/map.obj")" -eq $((12 * live))
check "the OBJ mesh names its materials" grep -q '^newmtl ' "$WORK/objects_render/map.mtl"
fails_with "ocg_render refuses a mesh it cannot write" "must end in .ply or .obj" "$BIN/ocg_render" --run "$WORK/objects" --mesh "$WORK/map.stl"
check "objects run is deterministic" objects_run "$WORK/objects2" "$WORK/objseq/camera.yaml" --snapshots none
check "identical object maps" diff "$WORK/objects/objects.json" "$WORK/objects2/objects.json"
check "ocg_eval objects" bash -c "'$BIN/ocg_eval' objects --gt '$WORK/objseq/objects_gt.json' --run '$WORK/objects' --json >'$WORK/metrics.json'"
check "most static objects mapped (Corr.S >= 6 of 8)" python3 -c "import json,sys; sys.exit(json.load(open('$WORK/metrics.json'))['corr_s'] < 6)"
check "the OCG input replays" "$BIN/ocg_replay" --input "$WORK/objects/ocg_observations.jsonl" --out "$WORK/objects_replay"
check "mode off removes nothing" objects_run "$WORK/objects_off" "$WORK/objseq/camera.yaml" --mode off --snapshots none
check "no removal in mode off" bash -c "! grep -q '\"removed\"' '$WORK/objects_off/changes.json'"
printf 'Objects:\n  min_confidence: 2\n' >"$WORK/bad_objects.yaml"
fails_with "bad Objects key named" "Objects.min_confidence" objects_run "$WORK/never_objects" "$WORK/bad_objects.yaml"
check "nothing written on failure" test ! -e "$WORK/never_objects/objects.json"
grep -v -e width -e height "$WORK/objseq/camera.yaml" >"$WORK/no_size.yaml"
# ORB-SLAM2's TUM files give no image size: objects takes it from the first image listed.
check "objects takes the image size from the frames' images" objects_run "$WORK/objects_no_size" "$WORK/no_size.yaml" --snapshots none
check "same object map as with the size in the settings" cmp "$WORK/objects/objects.json" "$WORK/objects_no_size/objects.json"
fails_with "objects without a size nor --frames names the keys" "this command needs Camera.width and Camera.height (or --frames" \
  "$BIN/ocg_slam" objects --trajectory "$WORK/objseq/groundtruth.txt" --detections "$WORK/objseq/detections" --settings "$WORK/no_size.yaml" --out "$WORK/never_objects"
sed 's#rgb/#missing/#' "$WORK/objseq/rgb.txt" >"$WORK/objseq/rgb_missing.txt"
fails_with "objects without a size and no readable image says so" "could be read to take the size from" \
  "$BIN/ocg_slam" objects --trajectory "$WORK/objseq/groundtruth.txt" --detections "$WORK/objseq/detections" --settings "$WORK/no_size.yaml" --frames "$WORK/objseq/rgb_missing.txt" --out "$WORK/never_objects"
fails_with "unknown OCG mode named" "OCG.mode" objects_run "$WORK/never_objects" "$WORK/objseq/camera.yaml" --mode sometimes

# tools/detection_stats.py on a constructed folder: 8 s at 30 Hz, a cup present throughout
# but missed for 3 frames (10-12) and 1 frame (50), reported as a bowl for 5 frames (70-74),
# and a book in the first 4 seconds only.
mkdir -p "$WORK/stats/detections"
python3 - "$WORK/stats/detections" <<'PY'
import sys
for f in range(240):
    lines = []
    if f not in (10, 11, 12, 50):
        lines.append("%d 100 100 50 60 0.60" % (45 if 70 <= f <= 74 else 41))
    if f < 120:
        lines.append("73 300 200 80 40 0.95")
    open("%s/%.6f.txt" % (sys.argv[1], 1000 + f / 30.0), "w").write("".join(l + "\n" for l in lines))
PY
check "detection_stats.py runs" python3 "$SRC/tools/detection_stats.py" --json "$WORK/stats"
python3 "$SRC/tools/detection_stats.py" --json "$WORK/stats" >"$WORK/stats.json"
stat() { python3 -c "import json,sys; print('%.3f' % json.load(open(sys.argv[1]))[sys.argv[2]])" "$WORK/stats.json" "$1"; }
check "two miss runs, of 3 and 1 frames" test "$(stat miss_run_mean_frames)" = 2.000 -a "$(stat miss_run_1)" = 0.500
check "4-second means 1.967 (4 misses) and 1 boxes a frame" test "$(stat window_max)" = 1.967 -a "$(stat window_min)" = 1.000
check "one class flip of 5 frames" test "$(stat flip_run_mean_frames)" = 5.000
check "scores: the book's 120 of 356 boxes from 0.9" test "$(stat score_from_0.9)" = 0.337
check "ocg_synth --detections-only --detector realistic" "$BIN/ocg_synth" --preset smoke --frames 5 --size 320x240 --detections-only --detector realistic --out "$WORK/realistic_det"
check "detections written, no images" test -e "$WORK/realistic_det/detections" -a ! -e "$WORK/realistic_det/rgb"
check "scene.yaml records the model" grep -q "model: realistic" "$WORK/realistic_det/scene.yaml"
fails_with "--detector-seed without the realistic detector" "needs --detector realistic" "$BIN/ocg_synth" --preset smoke --frames 2 --detector-seed 3 --out "$WORK/never_det"
fails_with "an unknown detector model names the choices" "independent or realistic" "$BIN/ocg_synth" --preset smoke --frames 2 --detector yolo --out "$WORK/never_det"

# A session pair: a later visit of a rendered scene, its changes in objects_gt.json.
check "ocg_synth session_a" "$BIN/ocg_synth" --preset session_a --frames 3 --size 320x240 --detections-only --out "$WORK/visit1"
check "ocg_synth --session-of" "$BIN/ocg_synth" --preset session_b --session-of "$WORK/visit1" --seed 2 --frames 3 --size 320x240 --detections-only --out "$WORK/visit2"
check "objects_gt.json lists 4 moves, 1 removal, 1 addition between the visits" python3 -c "
import json, sys, collections
gt = json.load(open(sys.argv[1]))
kinds = collections.Counter(c['type'] for c in gt['session']['changes'])
sys.exit(0 if gt['session']['index'] == 1 and kinds == {'moved': 4, 'removed': 1, 'added': 1} else 1)" "$WORK/visit2/objects_gt.json"
check "the later visit's timestamps follow the first visit's" test "$(awk '!/^#/ {print int($1); exit}' "$WORK/visit2/groundtruth.txt")" -gt 1045
fails_with "--session-of with an unknown preset names the choices" "session_b" "$BIN/ocg_synth" --preset zigzag --session-of "$WORK/visit1" --frames 2 --out "$WORK/never_visit"

# ocg_diff on two hand-made object maps: the cup stays, the laptop moves 1.5 m, the book goes.
mkdir -p "$WORK/diff"
cat >"$WORK/diff/before.json" <<'JSON'
{"format": "ocg-objects", "version": 1, "up": [0, 0, 1], "objects": [
 {"id": 1, "class_id": 41, "cuboid": {"centre": [0, 0, 0.8], "size": [0.09, 0.09, 0.1], "yaw": 0}},
 {"id": 2, "class_id": 63, "cuboid": {"centre": [1, 0, 0.8], "size": [0.33, 0.23, 0.03], "yaw": 0}},
 {"id": 3, "class_id": 73, "cuboid": {"centre": [-1, 0, 0.8], "size": [0.16, 0.23, 0.04], "yaw": 0}}]}
JSON
cat >"$WORK/diff/after.json" <<'JSON'
{"format": "ocg-objects", "version": 1, "up": [0, 0, 1], "objects": [
 {"id": 7, "class_id": 41, "cuboid": {"centre": [0.01, 0, 0.8], "size": [0.09, 0.09, 0.1], "yaw": 0}},
 {"id": 8, "class_id": 63, "cuboid": {"centre": [1, 1.5, 0.8], "size": [0.33, 0.23, 0.03], "yaw": 0}}]}
JSON
check "ocg_diff" "$BIN/ocg_diff" --before "$WORK/diff/before.json" --after "$WORK/diff/after.json" --snapshots "$WORK/diff/png"
output_has "one of each" "removed 1, added 0, moved 1, unchanged 1"
output_has "the laptop moved" "moved      2 laptop at (1.000, 0.000, 0.800) -> 8 laptop"
check "ocg_diff wrote the before/after pair" test -s "$WORK/diff/png/diff_before_top.png" -a -s "$WORK/diff/png/diff_after_objects.png"
echo "not a map" >"$WORK/diff/before.txt"
fails_with "ocg_diff refuses a foreign file, naming it" "before.txt' is not an object map" "$BIN/ocg_diff" --before "$WORK/diff/before.txt" --after "$WORK/diff/after.json"

report_and_exit
