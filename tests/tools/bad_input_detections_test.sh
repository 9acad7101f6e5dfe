#!/usr/bin/env bash
# Bad detection input, end to end (issue 16, kinds 3, 4 and 6): never silently ignored,
# never a late failure after a whole run, never a bare crash. Run by CTest:
#   bad_input_detections_test.sh <folder with the tool binaries>
set -u
BIN=$1
source "$(dirname "$0")/check_helpers.sh"

SEQ=$WORK/seq
check "render a small sequence" "$BIN/ocg_synth" --preset smoke --frames 30 --size 320x240 --out "$SEQ" --keyframe-interval 0 --log-level warn
FIRST=$(awk '!/^#/ { print $1; exit }' "$SEQ/rgb.txt")
LAST=$(awk '!/^#/ { t = $1 } END { print t }' "$SEQ/rgb.txt")
objects_run() {  # objects_run DETECTIONS OUT [extra args...]
  local detections=$1 out=$2
  shift 2
  "$BIN/ocg_slam" objects --trajectory "$SEQ/groundtruth.txt" --detections "$detections" --settings "$SEQ/camera.yaml" --out "$out" "$@"
}
slam_run() {  # slam_run DETECTIONS OUT [extra args...]
  local detections=$1 out=$2
  shift 2
  "$BIN/ocg_slam" run --settings "$SEQ/camera.yaml" --sequence "$SEQ" --detections "$detections" --out "$out" "$@"
}
check "the generated detections work" objects_run "$SEQ/detections" "$WORK/good" --frames "$SEQ/rgb.txt"

# Kind 3: files named by frame index match no frame: an error giving an expected name
# (from the frame list) and a name found.
mkdir "$WORK/by_index"
i=0
for file in $(ls "$SEQ/detections" | sort); do
  cp "$SEQ/detections/$file" "$WORK/by_index/$(printf '%06d' $i).txt"
  i=$((i + 1))
done
fails_with "objects: index-named files match no frame" "matches a frame" objects_run "$WORK/by_index" "$WORK/x" --frames "$SEQ/rgb.txt"
output_has "objects: the expected name is given" "e.g. '$FIRST.txt'"
output_has "objects: a name found is given" "such as '000000.txt'"
fails_with "run: index-named files match no frame" "such as '000000.txt'" slam_run "$WORK/by_index" "$WORK/x"
output_has "run: the expected name is given" "e.g. '$FIRST.txt'"
fails_with "objects without --frames: index names give no pose" "the frames (from the detection files' names) span 000000 .. 000029" objects_run "$WORK/by_index" "$WORK/x"

# Kind 3: normalized YOLO boxes (cls cx cy w h conf in 0..1): a warning naming the folder.
mkdir "$WORK/normalized"
for file in "$SEQ"/detections/*.txt; do
  awk 'function unit(v) { return v < 0 ? 0 : (v > 1 ? 1 : v) } { printf "%s %.6f %.6f %.6f %.6f %s\n", $1, unit(($2 + $4 / 2) / 320), unit(($3 + $5 / 2) / 240), unit($4 / 320), unit($5 / 240), $6 }' "$file" >"$WORK/normalized/$(basename "$file")"
done
check "objects on normalized boxes still runs" objects_run "$WORK/normalized" "$WORK/norm_out" --frames "$SEQ/rgb.txt"
output_has "objects warns that the boxes look normalized" "every box in '$WORK/normalized' lies within 0..1"
check "convert on normalized boxes" "$BIN/ocg_convert_detections" --from "$WORK/normalized" --to "$WORK/normalized.json"
output_has "convert (EAO) warns that the boxes look normalized" "every box in '$WORK/normalized' lies within 0..1"
check "convert normalized JSON back" "$BIN/ocg_convert_detections" --from "$WORK/normalized.json" --to "$WORK/normalized_back"
output_has "convert (JSON) warns naming the file" "every box in '$WORK/normalized.json' lies within 0..1"
check "pixel boxes give no such warning" objects_run "$SEQ/detections" "$WORK/good2" --frames "$SEQ/rgb.txt"
output_lacks "no normalized warning on pixel boxes" "lies within 0..1"

# Kind 3: a <timestamp>.txt that is not a readable file (a folder, a broken link).
cp -r "$SEQ/detections" "$WORK/with_dir"
rm "$WORK/with_dir/$LAST.txt"
mkdir "$WORK/with_dir/$LAST.txt"
fails_with "objects names the folder in a file's place" "'$WORK/with_dir/$LAST.txt' is a directory" objects_run "$WORK/with_dir" "$WORK/x" --frames "$SEQ/rgb.txt"
fails_with "run names the folder in a file's place" "'$WORK/with_dir/$LAST.txt' is a directory" slam_run "$WORK/with_dir" "$WORK/x"
fails_with "convert names the folder in a file's place" "'$WORK/with_dir/$LAST.txt' is a directory" "$BIN/ocg_convert_detections" --from "$WORK/with_dir" --to "$WORK/x.json"
rmdir "$WORK/with_dir/$LAST.txt"
ln -s "$WORK/nowhere.txt" "$WORK/with_dir/$LAST.txt"
fails_with "objects names a broken link" "'$WORK/with_dir/$LAST.txt' is a broken symbolic link" objects_run "$WORK/with_dir" "$WORK/x" --frames "$SEQ/rgb.txt"
mkdir "$WORK/images.json"
fails_with "convert reads a folder named .json as an EAO folder" "images.json' holds no .txt file" "$BIN/ocg_convert_detections" --from "$WORK/images.json" --to "$WORK/x" --log-level warn
check "nothing written on failure" test ! -e "$WORK/x"

# Kind 4: one malformed line in the last frame's file fails at start, with file:line and
# a word on --lenient; nothing is processed or written.
cp -r "$SEQ/detections" "$WORK/late_bad"
echo "56 10 20 30" >>"$WORK/late_bad/$LAST.txt"
LINE=$(wc -l <"$WORK/late_bad/$LAST.txt")
fails_with "run fails at start on the last file's bad line" "$WORK/late_bad/$LAST.txt:$LINE: expected 6 fields" slam_run "$WORK/late_bad" "$WORK/late_run"
output_has "run names --lenient" "--lenient"
output_lacks "run failed before the vocabulary and the first frame" "vocabulary"
check "run wrote nothing" test ! -e "$WORK/late_run"
fails_with "objects fails at start on the last file's bad line" "$WORK/late_bad/$LAST.txt:$LINE: expected 6 fields" objects_run "$WORK/late_bad" "$WORK/late_objects" --frames "$SEQ/rgb.txt"
output_has "objects names --lenient" "--lenient"
output_lacks "objects failed before the first frame" "ocg_slam objects:"
check "objects wrote nothing" test ! -e "$WORK/late_objects"
check "objects --lenient skips the line" objects_run "$WORK/late_bad" "$WORK/lenient_objects" --frames "$SEQ/rgb.txt" --lenient
output_has "the skipped line is a warning" "skipping malformed detection"
fails_with "convert names --lenient" "--lenient" "$BIN/ocg_convert_detections" --from "$WORK/late_bad" --to "$WORK/late.json"

# Kind 4: an output folder that cannot be written fails at start, naming the folder.
echo "a file" >"$WORK/a_file"
fails_with "run: --out under a file" "cannot create the output folder '$WORK/a_file/out'" slam_run "$SEQ/detections" "$WORK/a_file/out"
fails_with "objects: --out under a file" "cannot create the output folder '$WORK/a_file/out'" objects_run "$SEQ/detections" "$WORK/a_file/out" --frames "$SEQ/rgb.txt"
mkdir "$WORK/read_only"
chmod 555 "$WORK/read_only"
as_user=()
if [ "$(id -u)" -eq 0 ]; then  # root writes anywhere: run the tools as nobody
  if command -v setpriv >/dev/null; then
    chmod 755 "$WORK"
    as_user=(setpriv --reuid=65534 --regid=65534 --clear-groups)
  else
    as_user=(skip)
  fi
fi
if [ "${as_user[*]-}" != skip ]; then
  fails_with "run: a read-only --out is named at start" "the output folder '$WORK/read_only' is not writable" "${as_user[@]}" "$BIN/ocg_slam" run --settings "$SEQ/camera.yaml" --sequence "$SEQ" --detections "$SEQ/detections" --out "$WORK/read_only"
  output_lacks "run failed before the vocabulary and the first frame" "vocabulary"
  fails_with "objects: a read-only --out is named at start" "the output folder '$WORK/read_only' is not writable" "${as_user[@]}" "$BIN/ocg_slam" objects --trajectory "$SEQ/groundtruth.txt" --detections "$SEQ/detections" --settings "$SEQ/camera.yaml" --out "$WORK/read_only"
else
  echo "note: the read-only --out checks need setpriv when run as root; skipped"
fi

# Kind 6: an absurdly large detection file is refused, naming the file and the limit
# (a sparse file: no disk space used).
cp -r "$SEQ/detections" "$WORK/huge"
truncate -s 6G "$WORK/huge/$LAST.txt"
fails_with "objects refuses a 6 GB detection file" "detection file '$WORK/huge/$LAST.txt' is 6144.0 MiB, more than the limit of 16.0 MiB" objects_run "$WORK/huge" "$WORK/x" --frames "$SEQ/rgb.txt"
output_lacks "no bare bad_alloc" "bad_alloc"
fails_with "run refuses it at start" "more than the limit of 16.0 MiB" slam_run "$WORK/huge" "$WORK/x"
fails_with "convert refuses it" "more than the limit of 16.0 MiB" "$BIN/ocg_convert_detections" --from "$WORK/huge" --to "$WORK/x.json"
truncate -s 300M "$WORK/big.json"
fails_with "convert refuses a 300 MB JSON list" "'$WORK/big.json' is 300.0 MiB, more than the limit of 256.0 MiB" "$BIN/ocg_convert_detections" --from "$WORK/big.json" --to "$WORK/x"

# ocg_replay: a centroid given before the object's first observation is kept (the
# issue's four keyframes): object 3 gains doubt 30 in keyframe 3.
camera='"camera": {"fx": 500, "fy": 500, "cx": 320, "cy": 240, "width": 640, "height": 480}'
table='"T_cw": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]'
shelf='"T_cw": [-1,0,0,0, 0,1,0,0, 0,0,-1,0, 0,0,0,1]'
cat >"$WORK/early_centroid.jsonl" <<EOF
{"keyframe": 0, "timestamp": 0.0, $table, $camera, "observed": [1, 2], "centroids": {"1": [0, 0, 2], "2": [0.3, 0, 2], "3": [-0.3, 0, 2]}}
{"keyframe": 1, "timestamp": 0.5, $table, $camera, "observed": [1, 2, 3]}
{"keyframe": 2, "timestamp": 1.0, $shelf, $camera, "observed": [4], "centroids": {"4": [0, 0, -2]}}
{"keyframe": 3, "timestamp": 1.5, $table, $camera, "observed": [1, 2]}
EOF
check "ocg_replay on the four keyframes" "$BIN/ocg_replay" --input "$WORK/early_centroid.jsonl" --out "$WORK/early"
check "object 3 in state 3 at keyframe 2, state 4 with doubt 30 at keyframe 3" python3 -c "
import json, sys
lines = [json.loads(line) for line in open('$WORK/early/states.jsonl')]
state = lambda k: {o['id']: o for o in lines[k]['objects']}[3]
assert state(2)['state'] == 3, state(2)
assert state(3)['state'] == 4 and state(3)['doubt'] == 30 and state(3)['active_edge_rate'] == 1.0, state(3)
"

report_and_exit
