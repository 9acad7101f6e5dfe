#!/usr/bin/env bash
# Runs OCG-SLAM's main job on its embedded default and prints where the outputs are.
# Usage: tools/demo.sh [OUTPUT_FOLDER]     (default: out/demo)
#
# The embedded default is the generated `smoke` sequence: a table with a central
# partition, eight desk objects, a camera going round; the laptop is moved while the
# camera is on the other side. It runs the generator, then OCG-SLAM on the sequence:
# monocular SLAM with the object layer (cuboids from the detections, kept up to date by
# the Object Covisibility Graph), and scores the trajectory and the object map against
# the ground truth. The viewer (snapshots) is not built yet.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${OCG_BUILD_DIR:-$ROOT/build}
OUT=${1:-$ROOT/out/demo}
JOBS=$(nproc 2>/dev/null || echo 2)

"$ROOT/tools/install_deps.sh"
GENERATOR=()
[ -f "$BUILD/CMakeCache.txt" ] || { command -v ninja >/dev/null 2>&1 && GENERATOR=(-G Ninja); }
echo "== build"
cmake -S "$ROOT" -B "$BUILD" "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" --parallel "$JOBS" --target ocg_synth ocg_slam ocg_replay ocg_eval >/dev/null

echo "== demo"
echo "note: the viewer is not built yet: no snapshots"
mkdir -p "$OUT"
"$BUILD/tools/ocg_synth" --preset smoke --out "$OUT/sequence" --overwrite --log-level warn
"$BUILD/tools/ocg_slam" run --settings "$OUT/sequence/camera.yaml" --sequence "$OUT/sequence" \
  --detections "$OUT/sequence/detections" --out "$OUT/run" --log-level warn | sed -n '2,3p'
"$BUILD/tools/ocg_eval" ate --gt "$OUT/sequence/groundtruth.txt" --est "$OUT/run/CameraTrajectory.txt" \
  --align sim3 | awk '$1 == "rmse" {print "camera trajectory ATE RMSE (Sim(3) aligned): " $2 " m"}'
echo "object map against the ground truth (SPEC 4, aligned through the trajectory):"
"$BUILD/tools/ocg_eval" objects --gt "$OUT/sequence/objects_gt.json" --run "$OUT/run" \
  --groundtruth "$OUT/sequence/groundtruth.txt"
echo
echo "outputs:"
echo "  $OUT/sequence/           TUM-format sequence: rgb/, rgb.txt, groundtruth.txt,"
echo "                           detections/, objects_gt.json (the laptop's move), camera.yaml"
echo "  $OUT/run/                KeyFrameTrajectory.txt, CameraTrajectory.txt (TUM format), run.json"
echo "  $OUT/run/objects.json    the object map: cuboids with their OCG state"
echo "  $OUT/run/changes.json    change log: objects removed by the OCG (and merged duplicates)"
echo "  $OUT/run/ocg.json        the final Object Covisibility Graph"
