#!/usr/bin/env bash
# The smoke preset's first 300 frames: the sequence of slam_smoke_end_to_end,
# session_end_to_end and stop_end_to_end, which only read it. The suite generates it once
# for the three (about 20 CPU seconds each time), as the fixture smoke300 of
# tests/CMakeLists.txt:
#   smoke300.sh <folder with the tool binaries> <out folder>
# A test script sources this file and calls `smoke300 BIN [FOLDER]`: SMOKE is then FOLDER
# (the fixture's), or without one a sequence generated in $WORK/smoke.
generate_smoke300() {  # generate_smoke300 BIN OUT
  "$1/ocg_synth" --preset smoke --frames 300 --out "$2" --keyframe-interval 0 --overwrite \
    --log-level warn >/dev/null
}
smoke300() {  # smoke300 BIN [FOLDER]: sets SMOKE
  SMOKE=${2:-$WORK/smoke}
  [ -n "${2:-}" ] || generate_smoke300 "$1" "$SMOKE"
}
if [ "${BASH_SOURCE[0]}" = "$0" ]; then
  set -euo pipefail
  generate_smoke300 "${1:?usage: smoke300.sh BIN OUT}" "${2:?usage: smoke300.sh BIN OUT}"
fi
