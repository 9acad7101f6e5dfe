#!/usr/bin/env bash
# Regenerates thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc (see thirdparty/README.md).
# Usage: thirdparty/make_vocabulary.sh [BUILD_FOLDER] [SHARED_DATA_FOLDER]
# Needs the built tools (tools/test.sh builds them) and, for the real frames, the shared
# data folder (default ../shared/data beside the project); without it the vocabulary is
# trained on the synthetic images alone and the script says so.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${1:-$ROOT/build}
DATA=${2:-$ROOT/../shared/data}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

# Synthetic rooms: three presets with seeds other than the defaults (so that the
# vocabulary is not tuned to the exact sequences we evaluate on), one image a second.
SOURCES=()
for spec in straight_1:101 round_1:102 desk_static:103; do
  preset=${spec%%:*}
  seed=${spec##*:}
  echo "== rendering $preset (seed $seed)"
  "$BUILD/tools/ocg_synth" --preset "$preset" --seed "$seed" --out "$WORK/$preset" \
    --keyframe-interval 0 --log-level warn >/dev/null
  awk 'NR % 30 == 1 && $1 !~ /^#/' "$WORK/$preset/rgb.txt" >"$WORK/$preset/every30.txt"
  SOURCES+=(--images "$WORK/$preset/every30.txt")
done

# Real frames: TUM fr3 long_office and cabinet, EuRoC V1_01.
if [[ -d "$DATA" ]]; then
  SOURCES+=(--images "$DATA/tum_fr3_long_office/rgb.txt")
  SOURCES+=(--images "$DATA/tum_fr3_cabinet_keyframes/raw_imgs")
  SOURCES+=(--images "$DATA/euroc_v101_micro/mav0/cam0/data")
else
  echo "warning: $DATA not found: training on synthetic images only" >&2
fi

"$BUILD/tools/ocg_vocab" train "${SOURCES[@]}" --k 10 --L 5 --seed 42 \
  --out "$ROOT/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc"
"$BUILD/tools/ocg_vocab" info "$ROOT/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc"
