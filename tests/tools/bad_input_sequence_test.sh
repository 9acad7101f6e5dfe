#!/usr/bin/env bash
# End to end: bad image sequences given to ocg_slam (issue 16, kinds 1, 5 and 6): large
# images run, frame lists out of time order or with a repeated time fail naming both
# lines, a still camera ends with the reason it never initialized (also in run.json), a
# frame list that is not a file is named with what it is.
#   bad_input_sequence_test.sh <folder with the tool binaries> <project source folder>
set -u
BIN=$1
SRC=$2
source "$(dirname "${BASH_SOURCE[0]}")/check_helpers.sh"

slam() {  # slam <sequence folder> <out folder> [more options]
  local sequence=$1 out=$2
  shift 2
  "$BIN/ocg_slam" run --settings "$WORK/small/camera.yaml" --sequence "$sequence" --out "$out" "$@"
}
# A copy of the small sequence with its own rgb.txt (read from standard input).
with_list() {  # with_list <name>
  mkdir -p "$WORK/$1"
  ln -sfn "$WORK/small/rgb" "$WORK/$1/rgb"
  cat >"$WORK/$1/rgb.txt"
}

# Kind 1: large images. 1920x1080 aborted in cv::FAST at frame 0 before the FAST cells
# tiled every pyramid level exactly.
check "ocg_synth 1920x1080" "$BIN/ocg_synth" --preset smoke --frames 6 --size 1920x1080 --out "$WORK/large" --log-level warn
check "ocg_slam on 1920x1080 images" "$BIN/ocg_slam" run --settings "$WORK/large/camera.yaml" --sequence "$WORK/large" --out "$WORK/large_out" --log-level warn
check "large run wrote run.json" grep -q '"width": 1920' "$WORK/large_out/run.json"

check "ocg_synth small" "$BIN/ocg_synth" --preset smoke --frames 30 --out "$WORK/small" --log-level warn
frames() { grep -v '^#' "$WORK/small/rgb.txt"; }  # the 30 "timestamp path" lines

# Kind 5: timestamps. Backwards (the list reversed), one frame with an earlier time, and
# two frames with one time (not next to each other): each names both lines of rgb.txt.
{ echo "# reversed"; frames | tac; } | with_list backwards
t1=$(frames | sed -n 1p | cut -d' ' -f1)
t2=$(frames | sed -n 2p | cut -d' ' -f1)
fails_with "rgb.txt going backwards names both lines" "backwards/rgb.txt:3: frame time $(frames | sed -n 29p | cut -d' ' -f1) is earlier than line 2" \
  slam "$WORK/backwards" "$WORK/backwards_out"
check "nothing written for a rejected list" test ! -e "$WORK/backwards_out/run.json"
frames | awk -v t="$t1" 'NR == 5 { $1 = t - 0.5 } { print }' | with_list earlier
fails_with "a frame labelled with an earlier time" "earlier/rgb.txt:5: frame time" \
  slam "$WORK/earlier" "$WORK/earlier_out"
cp "$WORK/out" "$WORK/earlier.log"
check "... is said to be earlier than line 4" grep -qF "is earlier than line 4" "$WORK/earlier.log"
frames | awk -v t="$t2" 'NR == 7 { $1 = t } { print }' | with_list repeated
fails_with "a repeated time names the line it repeats" "repeated/rgb.txt:7: frame time $t2 repeats line 2 ('$t2')" \
  slam "$WORK/repeated" "$WORK/repeated_out"
# The same mechanism for the --frames list of `ocg_slam objects`.
frames | awk -v t="$t2" 'NR == 7 { $1 = t } { print }' >"$WORK/frames_repeated.txt"
fails_with "ocg_slam objects --frames with a repeated time" "frames_repeated.txt:7: frame time $t2 repeats line 2" \
  "$BIN/ocg_slam" objects --trajectory "$WORK/small/groundtruth.txt" --detections "$WORK/small/detections" \
  --settings "$WORK/small/camera.yaml" --frames "$WORK/frames_repeated.txt" --out "$WORK/objects_out"

# Reference data is read as the field's tools (TUM's associate.py, evo) read it: a
# ground-truth time listed on two consecutive lines, as in TUM's own fr2_desk
# groundtruth.txt, keeps its first pose with one warning naming the lines; lines out of
# order are sorted. The frame lists above stay strict.
awk '!/^#/ { n++ } { print } n == 5 && !done { print; done = 1 }' "$WORK/small/groundtruth.txt" >"$WORK/gt_repeated.txt"
repeated_line=$(grep -n . "$WORK/gt_repeated.txt" | awk -F: '!/^[0-9]+:#/ { n++ } n == 6 { print $1; exit }')
check "ocg_slam objects --trajectory with a repeated time" \
  "$BIN/ocg_slam" objects --trajectory "$WORK/gt_repeated.txt" --detections "$WORK/small/detections" \
  --settings "$WORK/small/camera.yaml" --out "$WORK/objects_repeated"
output_has "... warns once, naming both lines" "gt_repeated.txt: 1 repeated pose time (line $repeated_line repeats line $((repeated_line - 1))"
output_has "... and what it did" "kept the first pose of each time"
check "... and maps as with the file without the repeat" \
  "$BIN/ocg_slam" objects --trajectory "$WORK/small/groundtruth.txt" --detections "$WORK/small/detections" \
  --settings "$WORK/small/camera.yaml" --out "$WORK/objects_plain"
check "... the same objects" diff "$WORK/objects_repeated/objects.json" "$WORK/objects_plain/objects.json"
check "ocg_eval ate with the repeated ground truth" "$BIN/ocg_eval" ate --gt "$WORK/gt_repeated.txt" --est "$WORK/small/groundtruth.txt" --align se3
output_has "... warns" "1 repeated pose time"
output_has "... and the error is 0" "rmse    0.000000"
{ grep '^#' "$WORK/small/groundtruth.txt"; grep -v '^#' "$WORK/small/groundtruth.txt" | tac; } >"$WORK/gt_reversed.txt"
check "ocg_eval ate with the ground truth reversed" "$BIN/ocg_eval" ate --gt "$WORK/gt_reversed.txt" --est "$WORK/small/groundtruth.txt" --align se3
output_has "... warns that it sorted" "listed before an earlier time"
output_has "... and the error is 0" "rmse    0.000000"

# Kind 6: a still camera (the first image listed 12 times) never initializes, and says so
# at the default log level and in run.json.
first_image=$(frames | sed -n 1p | cut -d' ' -f2)
frames | head -n 12 | awk -v image="$first_image" '{ print $1, image }' | with_list still
check "a still camera runs to the end" slam "$WORK/still" "$WORK/still_out"
cp "$WORK/out" "$WORK/still.log"
check "... and says why it never initialized" grep -qF "never initialized in 12 frames: too little parallax" "$WORK/still.log"
check "run.json: initialized false" grep -q '"initialized": false' "$WORK/still_out/run.json"
check "run.json: frames tried" grep -q '"frames_tried": 12' "$WORK/still_out/run.json"
check "run.json: the reason" grep -q '"message": "never initialized in 12 frames: too little parallax' "$WORK/still_out/run.json"
check "a moving camera initializes" slam "$WORK/small" "$WORK/small_out"
check "run.json: initialized true" grep -q '"initialized": true' "$WORK/small_out/run.json"
DATA="$SRC/../shared/data"
if [ -d "$DATA/euroc_v101_micro" ]; then
  # Real: the first 4.7 s of EuRoC V1_01, before take-off.
  check "real still camera (EuRoC V1_01 before take-off)" "$BIN/ocg_slam" run --settings "$SRC/config/EuRoC.yaml" \
    --sequence "$DATA/euroc_v101_micro" --format euroc --out "$WORK/euroc_out"
  cp "$WORK/out" "$WORK/euroc.log"
  check "... says it never initialized, for lack of parallax" grep -qF "never initialized in 95 frames: too little parallax" "$WORK/euroc.log"
else
  echo "SKIPPED: the real still camera: $DATA/euroc_v101_micro not found"
fi

# Kind 6: a frame list that is not a file is named with what it is; an empty one too.
mkdir -p "$WORK/dir_list/rgb.txt"
fails_with "rgb.txt that is a directory" "cannot read '$WORK/dir_list/rgb.txt': it is a directory, not a file" \
  slam "$WORK/dir_list" "$WORK/dir_out"
mkdir -p "$WORK/fifo_list" && mkfifo "$WORK/fifo_list/rgb.txt"
# (timeout: a reader that opened the pipe would wait for a writer forever)
fails_with "rgb.txt that is a named pipe" "it is a named pipe (FIFO), not a file" \
  timeout 60 "$BIN/ocg_slam" run --settings "$WORK/small/camera.yaml" --sequence "$WORK/fifo_list" --out "$WORK/fifo_out"
echo "# no frames" | with_list empty
fails_with "rgb.txt with no frame" "'$WORK/empty/rgb.txt' lists no image" slam "$WORK/empty" "$WORK/empty_out"

report_and_exit
