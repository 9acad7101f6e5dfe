#!/usr/bin/env bash
# SLAM speed: runs ocg_slam on a generated sequence (default: the smoke preset, 640x480,
# 1000 features) and prints the per-frame tracking time and the per-keyframe local
# mapping and local bundle adjustment times from run.json. Target: median tracking time
# at most 25 ms per frame on a 2-core machine, so that 30 Hz input runs in real time.
# Usage: bench/slam_speed.sh [BUILD_FOLDER] [PRESET] [threaded]
set -euo pipefail
BUILD=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/build}
PRESET=${2:-smoke}
MODE=${3:-sequential}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
"$BUILD/tools/ocg_synth" --preset "$PRESET" --out "$OUT/seq" --keyframe-interval 0 --log-level warn >/dev/null
cp "$OUT/seq/camera.yaml" "$OUT/settings.yaml"
if [ "$MODE" = threaded ]; then printf 'System:\n  sequential: false\n' >>"$OUT/settings.yaml"; fi
"$BUILD/tools/ocg_slam" run --settings "$OUT/settings.yaml" --sequence "$OUT/seq" --out "$OUT/slam" --log-level warn | sed -n 2p
python3 - "$OUT/slam/run.json" <<'PY'
import json, sys
run = json.load(open(sys.argv[1]))
for stage, label in [("tracking_per_frame", "tracking per frame"),
                     ("local_mapping_per_keyframe", "local mapping per keyframe"),
                     ("local_ba_per_keyframe", "local BA per keyframe")]:
    t = run["timing"][stage]
    print(f"{label:28s} median {t['median_ms']:7.2f} ms   p95 {t['p95_ms']:7.2f} ms   (n = {t['count']})")
print(f"mode {run['mode']}, wall {run['wall_seconds']:.1f} s for {run['frames']} frames")
PY
