#!/bin/bash
# ORB-SLAM3 v1.0 as the anchor on TUM fr1_rpy's first 330 frames (issue 34, point 4):
# converts our default vocabulary to DBoW2's text format, compiles bench/orbslam3_mono.cc
# against an ORB-SLAM3 build, runs it (monocular, no viewer) and our ocg_slam on the same
# frames with the same vocabulary and camera, and prints frames tracked, the initialization
# frame and the ATE (Sim(3), every tracked frame, `ocg_eval ate`) of both.
#
#   bench/orbslam3_anchor.sh ORB_SLAM3_DIR [--pangolin PREFIX] [--data DIR] [--build DIR]
#                            [--runs N] [--pace S] [--out DIR]
#
# ORB_SLAM3_DIR: an ORB-SLAM3 v1.0 checkout built as its build.sh does (lib/libORB_SLAM3.so,
# Thirdparty/DBoW2/lib, Thirdparty/g2o/lib). --pangolin: where Pangolin is installed when
# not in a system path. --data: the clip (default $OCG_SHARED_DATA or ../shared/data, then
# tum_fr1_rpy_first330). --build: our build folder (default build). --runs: ORB-SLAM3 runs
# (its threads make each run differ; default 3). --pace: ORB-SLAM3 gets S times each
# frame's period (default 1, the camera's rate; more on a loaded machine, where its
# threads would otherwise get less time than a live camera gives them). --out: work folder
# (default a temporary one). docs/anchor_orbslam3.md says how ORB-SLAM3 was built here and
# what it gave.
set -euo pipefail

usage() { sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
[ $# -ge 1 ] || usage
ORB3=$(cd "$1" && pwd)
shift
SOURCE=$(cd "$(dirname "$0")/.." && pwd)
PANGOLIN=""
DATA_ROOT=${OCG_SHARED_DATA:-$SOURCE/../shared/data}
DATA=""
BUILD=$SOURCE/build
RUNS=3
PACE=1
OUT=""
while [ $# -gt 0 ]; do
  case "$1" in
    --pangolin) PANGOLIN=$2; shift 2 ;;
    --data) DATA=$2; shift 2 ;;
    --build) BUILD=$2; shift 2 ;;
    --runs) RUNS=$2; shift 2 ;;
    --pace) PACE=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    *) usage ;;
  esac
done
DATA=${DATA:-$DATA_ROOT/tum_fr1_rpy_first330}
for f in "$DATA/rgb.txt" "$DATA/groundtruth.txt" "$DATA/orbslam2_TUM1.yaml"; do
  [ -f "$f" ] || { echo "orbslam3_anchor: missing $f" >&2; exit 1; }
done
for f in "$ORB3/lib/libORB_SLAM3.so" "$ORB3/Thirdparty/DBoW2/lib/libDBoW2.so" \
         "$ORB3/Thirdparty/g2o/lib/libg2o.so"; do
  [ -f "$f" ] || { echo "orbslam3_anchor: missing $f (build ORB-SLAM3 first)" >&2; exit 1; }
done
for tool in ocg_vocab ocg_slam ocg_eval; do
  [ -x "$BUILD/tools/$tool" ] || { echo "orbslam3_anchor: no $BUILD/tools/$tool" >&2; exit 1; }
done
if [ -z "$OUT" ]; then OUT=$(mktemp -d /tmp/orbslam3_anchor.XXXXXX); fi
mkdir -p "$OUT"
echo "orbslam3_anchor: work folder $OUT"

# 1. The same vocabulary: ours in DBoW2's text format (ocg_vocab writes ORB-SLAM2's
#    ORBvoc.txt layout, which ORB-SLAM3's DBoW2 reads).
VOCABULARY=$OUT/ocg_orb_vocabulary.txt
"$BUILD/tools/ocg_vocab" convert --in "$SOURCE/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc" \
  --out "$VOCABULARY" --text

# 2. The same camera: ORB-SLAM2's TUM1 file in ORB-SLAM3 v1.0's settings layout
#    (File.version "1.0", Camera1.* intrinsics and distortion, an integer frame rate).
SETTINGS=$OUT/orbslam3_TUM1.yaml
python3 - "$DATA/orbslam2_TUM1.yaml" "$SETTINGS" <<'EOF'
import re, sys
values = {}
for line in open(sys.argv[1]):
    m = re.match(r'\s*([A-Za-z0-9_.]+)\s*:\s*([^#\s]+)', line)
    if m:
        values[m.group(1)] = m.group(2)
def get(key):
    if key not in values:
        sys.exit('orbslam3_anchor: %s has no %s' % (sys.argv[1], key))
    return values[key]
out = ['%YAML:1.0', 'File.version: "1.0"', 'Camera.type: "PinHole"']
for key in ['fx', 'fy', 'cx', 'cy', 'k1', 'k2', 'p1', 'p2', 'k3']:
    if 'Camera.' + key in values or key in ['fx', 'fy', 'cx', 'cy']:
        out.append('Camera1.%s: %s' % (key, float(get('Camera.' + key))))
out += ['Camera.width: %d' % int(values.get('Camera.width', 640)),
        'Camera.height: %d' % int(values.get('Camera.height', 480)),
        'Camera.fps: %d' % round(float(get('Camera.fps'))),
        'Camera.RGB: %d' % int(float(get('Camera.RGB')))]
out += ['ORBextractor.nFeatures: %d' % int(get('ORBextractor.nFeatures')),
        'ORBextractor.scaleFactor: %s' % float(get('ORBextractor.scaleFactor')),
        'ORBextractor.nLevels: %d' % int(get('ORBextractor.nLevels')),
        'ORBextractor.iniThFAST: %d' % int(get('ORBextractor.iniThFAST')),
        'ORBextractor.minThFAST: %d' % int(get('ORBextractor.minThFAST'))]
out += ['Viewer.KeyFrameSize: 0.05', 'Viewer.KeyFrameLineWidth: 1.0', 'Viewer.GraphLineWidth: 0.9',
        'Viewer.PointSize: 2.0', 'Viewer.CameraSize: 0.08', 'Viewer.CameraLineWidth: 3.0',
        'Viewer.ViewpointX: 0.0', 'Viewer.ViewpointY: -0.7', 'Viewer.ViewpointZ: -1.8',
        'Viewer.ViewpointF: 500.0']
open(sys.argv[2], 'w').write('\n'.join(out) + '\n')
EOF

# 3. The driver, compiled against the ORB-SLAM3 build with the flags its libraries were built
#    with: -march=native (ORB-SLAM3, its DBoW2 and g2o all use it; Eigen's alignment of the
#    objects the driver and the library share depends on it) and C++11 with its
#    COMPILEDWITHC11 (docs/anchor_orbslam3.md).
DRIVER=$OUT/orbslam3_mono
PANGOLIN_FLAGS=()
if [ -n "$PANGOLIN" ]; then
  # shellcheck disable=SC2054  # -Wl takes commas
  PANGOLIN_FLAGS=(-I"$PANGOLIN/include" -L"$PANGOLIN/lib" -Wl,-rpath,"$PANGOLIN/lib")
fi
# shellcheck disable=SC2046  # pkg-config's flags are meant to split into words
g++ -std=c++11 -DCOMPILEDWITHC11 -O2 -march=native -o "$DRIVER" "$SOURCE/bench/orbslam3_mono.cc" \
  -I"$ORB3" -I"$ORB3/include" -I"$ORB3/include/CameraModels" -I"$ORB3/Thirdparty/Sophus" \
  -I/usr/include/eigen3 $(pkg-config --cflags opencv4) "${PANGOLIN_FLAGS[@]}" \
  -L"$ORB3/lib" -Wl,-rpath,"$ORB3/lib" \
  -L"$ORB3/Thirdparty/DBoW2/lib" -Wl,-rpath,"$ORB3/Thirdparty/DBoW2/lib" \
  -L"$ORB3/Thirdparty/g2o/lib" -Wl,-rpath,"$ORB3/Thirdparty/g2o/lib" \
  -lORB_SLAM3 -lDBoW2 -lg2o -lpangolin -lGLEW -lGL $(pkg-config --libs opencv4) \
  -lboost_serialization -lcrypto -lpthread

# Frames tracked after the first one, and the ATE, of a TUM trajectory.
summarize() {  # NAME TRAJECTORY
  local ate
  ate=$("$BUILD/tools/ocg_eval" ate --gt "$DATA/groundtruth.txt" --est "$2" --align sim3 --json)
  python3 - "$1" "$DATA/rgb.txt" "$2" "$ate" <<'EOF'
import json, sys
name, rgb, trajectory, ate = sys.argv[1], sys.argv[2], sys.argv[3], json.loads(sys.argv[4])
frames = [l.split()[0] for l in open(rgb) if l.strip() and not l.startswith('#')]
index = {float(t): i for i, t in enumerate(frames)}
rows = [float(l.split()[0]) for l in open(trajectory) if l.strip() and not l.startswith('#')]
tracked = sorted(min(index, key=lambda t: abs(t - r)) for r in rows)
first = index[tracked[0]] if tracked else -1
after = len(frames) - first if tracked else 0
rmse = ate.get('translation', ate).get('rmse')
print('| %s | %d | %d / %d (%.1f %%) | %d | %.2f cm |' % (
    name, first, len(rows), after, 100.0 * len(rows) / max(after, 1),
    ate.get('pairs', len(rows)), 100 * rmse))
EOF
}

TABLE=$OUT/table.md
echo "| system | first tracked frame | frames tracked after it | ATE pairs | ATE RMSE (Sim(3)) |" > "$TABLE"
echo "|---|---|---|---|---|" >> "$TABLE"

# 4. Ours (sequential mode: deterministic).
"$BUILD/tools/ocg_slam" run --settings "$DATA/orbslam2_TUM1.yaml" --sequence "$DATA" \
  --out "$OUT/ours" > "$OUT/ours.log" 2>&1
summarize "OCG-SLAM (ocg_slam run)" "$OUT/ours/CameraTrajectory.txt" >> "$TABLE"

# 5. ORB-SLAM3, several runs (threaded: runs differ).
for run in $(seq 1 "$RUNS"); do
  mkdir -p "$OUT/orbslam3_$run"
  if "$DRIVER" "$VOCABULARY" "$SETTINGS" "$DATA" "$OUT/orbslam3_$run" --pace "$PACE" \
       > "$OUT/orbslam3_$run/log.txt" 2>&1 && [ -s "$OUT/orbslam3_$run/CameraTrajectory.txt" ]; then
    summarize "ORB-SLAM3 v1.0, run $run" "$OUT/orbslam3_$run/CameraTrajectory.txt" >> "$TABLE"
  else
    echo "| ORB-SLAM3 v1.0, run $run | failed or tracked nothing: $OUT/orbslam3_$run/log.txt | | | |" >> "$TABLE"
  fi
  grep "^orbslam3_mono:" "$OUT/orbslam3_$run/log.txt" || true
done
cat "$TABLE"
