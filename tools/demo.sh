#!/usr/bin/env bash
# Runs OCG-SLAM's main job on its embedded default and prints where the outputs are.
# Usage: tools/demo.sh [OUTPUT_FOLDER]     (default: out/demo)
#
# The embedded default is the generated `smoke` sequence: a table with a central
# partition, eight desk objects, a camera going round; the laptop is moved while the
# camera is on the other side. It runs the generator, monocular SLAM on the sequence
# (trajectories, scored against the ground truth), and the Object Covisibility Graph on
# the sequence's oracle keyframe stream (ground-truth poses, perfect data association),
# in paper and in improved mode. The object map and the viewer are not built yet: the
# OCG cannot run on SLAM keyframes until the object layer exists.
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
echo "note: the object map and the snapshots do not exist yet; this runs the generator, the"
echo "      monocular SLAM and the OCG on the generator's oracle keyframes"
mkdir -p "$OUT"
"$BUILD/tools/ocg_synth" --preset smoke --out "$OUT/sequence" --overwrite --log-level warn
"$BUILD/tools/ocg_slam" run --settings "$OUT/sequence/camera.yaml" --sequence "$OUT/sequence" \
  --out "$OUT/slam" --log-level warn | sed -n 2p
"$BUILD/tools/ocg_eval" ate --gt "$OUT/sequence/groundtruth.txt" --est "$OUT/slam/CameraTrajectory.txt" \
  --align sim3 | awk '$1 == "rmse" {print "camera trajectory ATE RMSE (Sim(3) aligned): " $2 " m"}'
for mode in paper improved; do
  "$BUILD/tools/ocg_replay" --input "$OUT/sequence/oracle_observations.jsonl" --out "$OUT/ocg_$mode" \
    --mode "$mode" --log-level warn | sed -n 1p
done
echo
echo "outputs:"
echo "  $OUT/sequence/                 TUM-format sequence: rgb/, rgb.txt, groundtruth.txt,"
echo "                                 detections/, objects_gt.json (the laptop's move), camera.yaml"
echo "  $OUT/slam/                     KeyFrameTrajectory.txt, CameraTrajectory.txt (TUM format), run.json"
echo "  $OUT/ocg_paper/changes.json    change log: objects removed from the map (paper mode)"
echo "  $OUT/ocg_paper/states.jsonl    every object's state, DoubtValue and ActiveEdgeRate per keyframe"
echo "  $OUT/ocg_paper/ocg.json        the final Object Covisibility Graph"
echo "  $OUT/ocg_improved/             the same in improved mode"
