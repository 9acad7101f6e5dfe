#!/usr/bin/env bash
# Runs OCG-SLAM's main job on its embedded default and prints where the outputs are.
# Usage: tools/demo.sh [OUTPUT_FOLDER]     (default: out/demo)
#
# The SLAM pipeline (tracking, object map, snapshots) is not built yet. Until it is, this
# runs the most complete pipeline that exists: the Object Covisibility Graph change
# detection on the shipped example keyframe stream (tests/data/ocg_example.jsonl, the
# paper's Fig. 4/5 story), in paper mode and in improved mode.
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
cmake --build "$BUILD" --parallel "$JOBS" --target ocg_replay ocg_eval >/dev/null

echo "== demo"
echo "note: the SLAM pipeline does not exist yet; running the most complete pipeline that"
echo "      does: OCG change detection on tests/data/ocg_example.jsonl"
for mode in paper improved; do
  "$BUILD/tools/ocg_replay" --input "$ROOT/tests/data/ocg_example.jsonl" --out "$OUT/$mode" \
    --mode "$mode" --log-level warn | sed -n 1p
done
echo
echo "outputs:"
echo "  $OUT/paper/states.jsonl     states, DoubtValue and ActiveEdgeRate per keyframe"
echo "  $OUT/paper/changes.json     change log: objects removed from the map"
echo "  $OUT/paper/ocg.json         the final Object Covisibility Graph"
echo "  $OUT/improved/              the same in improved mode"
