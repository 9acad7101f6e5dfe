#!/usr/bin/env bash
# Generator speed on one core: renders the smoke preset (640x480) pinned to CPU 0 and
# prints frames per second with the time per stage. Target: at least 20 frames/s.
# Usage: bench/synth_speed.sh [BUILD_FOLDER]
set -euo pipefail
BUILD=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/build}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
taskset -c 0 "$BUILD/tools/ocg_synth" --preset smoke --out "$OUT/smoke" --log-level warn | sed -n '2p;4p'
