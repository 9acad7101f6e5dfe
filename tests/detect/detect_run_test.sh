#!/usr/bin/env bash
# `ocg_slam run --detect` (the detector on each frame, on the image reader thread) against
# `ocg_detect` then `ocg_slam run --detections` on the first frames of the real fr1_rpy
# clip, sequential: the same files. (ocg_detect's detections.json keeps the network's
# unrounded corners, the EAO files 6 digits: a run on it is not compared.) Skips without the clip or
# the model (tools/get_detector.sh); the missing-model message is checked always.
set -euo pipefail
TOOLS="$1"
SRC="$2"
FRAMES=40
WORK="$(mktemp -d)"
trap 'rm -rf "${WORK}"' EXIT
fail() { echo "FAIL: $1"; [ -f "${2:-}" ] && tail -20 "$2"; exit 1; }

DATA="$SRC/../shared/data/tum_fr1_rpy_first330"
[ -n "${OCG_SHARED_DATA:-}" ] && DATA="$OCG_SHARED_DATA/tum_fr1_rpy_first330"
MODEL="${OCG_DETECTOR_MODEL:-$SRC/models/nanodet/nanodet.onnx}"

# The missing model is named, with how to get one, before any frame.
if [ -d "$DATA" ]; then
  if OCG_DETECTOR_MODEL="$WORK/none.onnx" "$TOOLS/ocg_slam" run --settings "$DATA/orbslam2_TUM1.yaml" \
    --sequence "$DATA" --detect --out "$WORK/no_model" >"$WORK/no_model.log" 2>&1; then
    fail "a run without the model succeeded" "$WORK/no_model.log"
  fi
  grep -q "no detector model at '$WORK/none.onnx'" "$WORK/no_model.log" ||
    fail "the missing model is not named" "$WORK/no_model.log"
fi
if [ ! -d "$DATA" ] || [ ! -f "$MODEL" ]; then
  echo "SKIPPED: needs $DATA (set OCG_SHARED_DATA) and the model $MODEL (tools/get_detector.sh)"
  exit 0
fi

mkdir -p "$WORK/list"
ln -s "$DATA/rgb" "$WORK/list/rgb"
awk -v frames="$FRAMES" '!/^#/ && kept < frames { print; kept++ }' "$DATA/rgb.txt" >"$WORK/list/rgb.txt"
"$TOOLS/ocg_detect" --images "$WORK/list/rgb.txt" --out "$WORK/det" --model "$MODEL" --json \
  >"$WORK/ocg_detect.log" 2>&1 || fail "ocg_detect failed" "$WORK/ocg_detect.log"
run() {  # NAME ARGS...
  local name="$1"
  shift
  "$TOOLS/ocg_slam" run --settings "$DATA/orbslam2_TUM1.yaml" --sequence "$DATA" \
    --max-frames "$FRAMES" --snapshots none --out "$WORK/$name" "$@" >"$WORK/$name.log" 2>&1 ||
    fail "ocg_slam run $* failed" "$WORK/$name.log"
}
run files --detections "$WORK/det"
run json --detections "$WORK/det/detections.json"  # reads the JSON list directly
OCG_DETECTOR_MODEL="$MODEL" run detect --detect --read-ahead 2
for name in detect; do
  for file in CameraTrajectory.txt KeyFrameTrajectory.txt map_points.ply objects.json \
    changes.json ocg.json ocg_observations.jsonl; do
    cmp -s "$WORK/files/$file" "$WORK/$name/$file" ||
      fail "$file differs between --detections DIR and $name"
  done
done
# The detector ran on every frame, on the reader thread, and found what ocg_detect found.
boxes=$(cat "$WORK"/det/*.txt | wc -l)
python3 - "$WORK/detect/run.json" "$boxes" "$FRAMES" <<'PY' || fail "run.json's reader section"
import json, sys
reader = json.load(open(sys.argv[1]))["reader"]
assert reader["boxes"] == int(sys.argv[2]), (reader["boxes"], sys.argv[2])
assert reader["detect_per_frame"]["count"] == int(sys.argv[3]), reader
assert reader["read_ahead"] == 2 and reader["detections"].startswith("NanoDet"), reader
print(f"detector {reader['detect_per_frame']['median_ms']:.0f} ms/frame (CPU of the reader thread "
      f"{reader['detect_cpu_per_frame']['median_ms']:.0f} ms), tracking waited "
      f"{reader['frame_wait_per_frame']['median_ms']:.0f} ms/frame, {reader['boxes']} boxes")
PY
grep -q "detector: $boxes boxes" "$WORK/detect.log" || fail "no detector summary" "$WORK/detect.log"
echo "PASS: --detect gives the files of ocg_detect then --detections, $FRAMES frames"
