#!/usr/bin/env bash
# Soak: does a long run on a path that only revisits keep its memory flat?
# (docs/robustness.md, "Long runs")
#
#   tools/soak.sh [MINUTES] [--preset NAME] [--frames N] [--out DIR] [--bin DIR]
#                 [--data DIR] [--max-growth PERCENT] [--max-fps N] [--sample-seconds S]
#
# Renders a preset once (ocg_synth --detector realistic, kept in --data), builds from it a
# long sequence played forward and back with fresh timestamps (no frame after the first
# pass shows anything new), runs `ocg_slam run` on it threaded with detections for
# MINUTES (default 60), then stops it with SIGINT, which makes it write every output and
# its map. Every S s (10) the run logs its frames, keyframes, map points, objects and
# resident memory; they go to OUT/soak.csv and OUT/soak.svg. At the end: the growth
# after the first pass (resident memory, keyframes, map points). Stopping the soak
# (Ctrl-C, SIGTERM) stops the run the same way: nothing is lost.
#
#   MINUTES          how long to run (default 60)
#   --preset NAME    ocg_synth preset (default round_2)
#   --frames N       only the preset's first N frames per pass (default: all)
#   --out DIR        results (default soak_out): soak.csv, soak.svg, run/, run.log, soak.ocgmap
#   --bin DIR        ocg_synth and ocg_slam (default build/tools)
#   --data DIR       where rendered presets are kept (default OUT/data)
#   --max-growth P   exit 1 when resident memory grows more than P % after the first pass
#   --max-fps N      the sequence holds enough passes for MINUTES at up to N frames a second
#                    (default 50; a small scene on a fast machine runs faster: the run must
#                    still be going when the soak stops it)
#   --sample-seconds S  seconds between the run's samples (default 10)
# Exit status: 0 when the run wrote its outputs (and, with --max-growth, the growth is
# within it), 1 otherwise, 2 for a wrong command line.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
usage() { sed -n '2,27p' "$0" | sed 's/^# \{0,1\}//'; }

minutes=60 preset=round_2 frames=0 out=soak_out bin="$HERE/../build/tools" data="" max_growth="" max_fps=50 sample_seconds=10
while [ $# -gt 0 ]; do
  case $1 in
    -h | --help) usage; exit 0 ;;
    --preset) preset=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --max-growth) max_growth=$2; shift 2 ;;
    --max-fps) max_fps=$2; shift 2 ;;
    --sample-seconds) sample_seconds=$2; shift 2 ;;
    [0-9]*) minutes=$1; shift ;;
    *) echo "soak.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$minutes" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "soak.sh: MINUTES must be a number, got '$minutes'" >&2; exit 2; }
[[ "$sample_seconds" =~ ^[1-9][0-9]*$ ]] ||
  { echo "soak.sh: --sample-seconds must be a whole number of seconds, got '$sample_seconds'" >&2; exit 2; }
for tool in ocg_synth ocg_slam; do
  [ -x "$bin/$tool" ] || { echo "soak.sh: no $bin/$tool (build it, or give --bin)" >&2; exit 2; }
done
mkdir -p "$out"
out=$(cd "$out" && pwd)
data=${data:-$out/data}

# The preset, rendered once.
source_name=$preset
[ "$frames" -gt 0 ] && source_name="${preset}_first$frames"
source="$data/$source_name"
if [ ! -f "$source/rgb.txt" ]; then
  echo "soak: rendering $preset (once, into $source)"
  limit=()
  [ "$frames" -gt 0 ] && limit=(--frames "$frames")
  "$bin/ocg_synth" --preset "$preset" --detector realistic "${limit[@]}" --out "$source" \
    --keyframe-interval 0 --overwrite --log-level warn >/dev/null
fi

# The long sequence: forward and back, enough passes for MINUTES at up to --max-fps frames
# a second, each frame with a fresh timestamp at the preset's frame rate; images and
# detection files are links to the preset's.
sequence="$out/sequence"
passes=$(python3 "$HERE/soak_sequence.py" "$source" "$sequence" "$minutes" "$max_fps")
settings="$out/settings.yaml"
{
  grep -v '^System' "$source/camera.yaml"
  echo "System:"
  echo "  sequential: false"
} >"$settings"
pass_frames=$(grep -vc '^#' "$source/rgb.txt")
total=$(grep -vc '^#' "$sequence/rgb.txt")
echo "soak: $minutes min on $preset, $pass_frames frames a pass forward and back, $passes passes ($total frames) at most, threaded, detections on"

rm -rf "$out/run"
"$bin/ocg_slam" run --settings "$settings" --sequence "$sequence" \
  --detections "$sequence/detections" --snapshots none --out "$out/run" \
  --save-map "$out/soak.ocgmap" --progress-seconds "$sample_seconds" >"$out/run.log" 2>&1 &
pid=$!
stopped=""
stop_run() {  # the run writes everything on SIGINT; the soak then reports
  stopped=${1:-time}
  kill -s INT "$pid" 2>/dev/null || true
}
trap 'stop_run signal' INT TERM
end=$(python3 -c "import time,sys; print(time.time() + 60 * float(sys.argv[1]))" "$minutes")
while kill -0 "$pid" 2>/dev/null; do
  if [ -z "$stopped" ] && python3 -c "import time,sys; sys.exit(time.time() < float(sys.argv[1]))" "$end"; then
    stop_run time
  fi
  sleep 1 || true
done
code=0
wait "$pid" || code=$?
trap - INT TERM
echo "soak: the run ended with exit code $code (130: stopped by SIGINT, as planned after $minutes min)"
python3 "$HERE/soak_report.py" "$out/run.log" "$out/soak.csv" "$out/soak.svg" "$pass_frames" \
  ${max_growth:+--max-growth "$max_growth"} || code=1
if [ -f "$out/run/run.json" ] && python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$out/run/run.json"; then
  echo "soak: the run's outputs: $out/run/ (run.json, trajectories, objects), map $out/soak.ocgmap"
else
  echo "soak: the run wrote no run.json (see $out/run.log)"
  code=1
fi
[ "$code" -eq 130 ] && code=0
exit "$code"
