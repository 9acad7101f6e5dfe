#!/usr/bin/env bash
# The default detector measured (docs/detector.md): on the 20 real fr3 long_office frames
# against the reference YOLO boxes (matched share at IoU >= 0.5 with the same class,
# unmatched boxes per frame, per class) at several score thresholds; cars found on KITTI
# 07 with and without tiles; time per frame on one core.
# usage: bench/detector_bench.sh [BUILD_DIR] [DATA_DIR]   (defaults: build, ../shared/data)
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
BUILD="${1:-${HERE}/../build}"
DATA="${2:-${HERE}/../../shared/data}"
OUT="$(mktemp -d "${TMPDIR:-/tmp}/ocg-detector-bench.XXXXXX")"
trap 'rm -rf "${OUT}"' EXIT
DETECT="${BUILD}/tools/ocg_detect"
EVAL="/usr/bin/python3 ${HERE}/detector_eval.py"
FR3="${DATA}/tum_fr3_long_office"
KITTI="${DATA}/kitti_07_first160"

echo "== fr3 long_office, 20 frames, one core"
"${DETECT}" --images "${FR3}/rgb.txt" --out "${OUT}/fr3" --score 0.3 --threads 1 2>/dev/null | sed -n 2p
for score in 0.3 0.35 0.4 0.45 0.5; do
  printf "score %-5s " "${score}"
  ${EVAL} --frames "${FR3}/rgb.txt" --detections "${OUT}/fr3" --reference "${FR3}/detections" \
    --min-score "${score}" --brief
done
echo "-- per class at the default score 0.4"
${EVAL} --frames "${FR3}/rgb.txt" --detections "${OUT}/fr3" --reference "${FR3}/detections" \
  --min-score 0.4 | tail -n +2

for tile in auto off; do
  echo "== KITTI 07, 160 frames (1226x370 grey), tiles ${tile}, one core"
  "${DETECT}" --images "${KITTI}/rgb.txt" --out "${OUT}/kitti_${tile}" --tile "${tile}" --threads 1 \
    2>/dev/null | sed -n 2p
  ${EVAL} --frames "${KITTI}/rgb.txt" --detections "${OUT}/kitti_${tile}" --count-class 2
done
