#!/usr/bin/env bash
# Runs OCG-SLAM's main job on its embedded default and prints where the outputs are.
# Usage: tools/demo.sh [OUTPUT_FOLDER]     (default: out/demo)
#
# The embedded default is the generated `smoke` sequence: a table with a central
# partition, eight desk objects, a camera going round; the laptop is moved while the
# camera is on the other side. It runs the generator, then OCG-SLAM on the sequence:
# monocular SLAM with the object layer (cuboids from the detections, kept up to date by
# the Object Covisibility Graph), and scores the trajectory and the object map against
# the ground truth, and renders snapshots of the map (before the laptop's removal and at
# the end) and of the last frame.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${OCG_BUILD_DIR:-$ROOT/build}
OUT=${1:-$ROOT/out/demo}
JOBS=$(nproc 2>/dev/null || echo 2)

"$ROOT/tools/install_deps.sh"
GENERATOR=()
[ -f "$BUILD/CMakeCache.txt" ] || { command -v ninja >/dev/null 2>&1 && GENERATOR=(-G Ninja); }
echo "== build of the tools and the Python module (the first time about 12 minutes on 2 cores; full log in $BUILD/demo_build.log)"
# The flags of tools/test.sh (-DOCG_WERROR=ON), so that it reuses this build instead of
# compiling everything again.
cmake -S "$ROOT" -B "$BUILD" "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE=Release -DOCG_WERROR=ON >/dev/null
# Every tool and the Python module: what the README's getting started uses after the demo.
TARGETS=(ocg_synth ocg_slam ocg_eval ocg_render ocg_diff ocg_replay ocg_detect
  ocg_convert_detections ocg_vocab)
# The list is read whole before grep: `cmake | grep -q` under pipefail fails when grep
# exits at its match before cmake has written the rest (SIGPIPE).
BUILD_TARGETS=$(cmake --build "$BUILD" --target help 2>/dev/null || true)
grep -qw ocg_python <<<"$BUILD_TARGETS" && TARGETS+=(ocg_python)
# Progress every 20 steps (Ninja's "[done/total]", Make's "[ n%]"); the whole log on failure.
set +e
cmake --build "$BUILD" --parallel "$JOBS" --target "${TARGETS[@]}" 2>&1 |
  tee "$BUILD/demo_build.log" |
  awk 'match($0, /^\[ *[0-9]+(\/[0-9]+|%)\]/) {
         if (++steps % 20 == 0) { print "  built " substr($0, RSTART, RLENGTH); fflush() } }'
status=${PIPESTATUS[0]}
set -e
if [ "$status" -ne 0 ]; then
  tail -n 40 "$BUILD/demo_build.log"
  echo "demo: the build failed (whole log: $BUILD/demo_build.log)" >&2
  exit 1
fi

echo "== demo"
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
row() { printf '  %-40s %s\n' "$1" "$2"; }
row "$OUT/sequence/" "TUM-format sequence: rgb/, rgb.txt, groundtruth.txt, detections/,"
row "" "objects_gt.json (the laptop's move), camera.yaml"
row "$OUT/run/" "KeyFrameTrajectory.txt, CameraTrajectory.txt (TUM format), run.json"
row "$OUT/run/objects.json" "the object map: cuboids with their OCG state"
row "$OUT/run/changes.json" "change log: objects moved or removed, seen by the OCG (and merged duplicates)"
row "$OUT/run/ocg.json" "the final Object Covisibility Graph"
row "$OUT/run/map_points.ply" "the map points (ASCII PLY)"
row "$OUT/run/snapshots/" "PNGs: final_{follow,top,three_quarter,objects}.png (the map),"
row "" "final_frame.png (the last frame with detections and cuboids),"
row "" "before_first_removal_objects.png (the laptop in red, about to be removed)"
