#!/usr/bin/env bash
# Builds OCG-SLAM with a sanitizer in a build folder of its own and runs the tests under it.
# Exits non-zero on any sanitizer report, on a failing test or on a failing build.
set -euo pipefail

usage() {
  cat <<'EOF'
Usage: tools/sanitize.sh [--smoke] address|undefined|thread
       tools/sanitize.sh --help

  address    AddressSanitizer, LeakSanitizer and UndefinedBehaviorSanitizer together: the
             whole test suite.
  undefined  UndefinedBehaviorSanitizer alone (no memory overhead): the whole test suite.
  thread     ThreadSanitizer: the unit tests that start threads (OcgManager)
             and a threaded end-to-end run of ocg_slam (local mapping and loop closing on
             their threads, global bundle adjustment on its own, the OCG on its thread
             through --detections).
  --smoke    with address: the same flags on the OCG's ocg_test (its thread included);
             a few minutes on 2 cores. The suite runs ocg_test and the readers under
             clang's address and undefined in fuzz_smoke (tools/fuzz.sh --tests), on the
             fuzzers' build.

Build folders (beside build/, or under $OCG_SANITIZE_ROOT): build-asan (--smoke too),
build-ubsan, build-tsan. gcc, RelWithDebInfo (-O1: a sanitizer's stacks stay
readable) with -fno-omit-frame-pointer; ccache when present. Every report is written to
<build folder>/sanitizer-logs/ and printed at the end; the first report ends the process
(halt_on_error), and any report makes this script fail, even one from a program a test
expected to fail. Except: UBSan inside the address build (gcc) prints to stderr only; the
script also searches the tests' output for it, but a report a test script swallows is
seen by the undefined mode alone.
Environment: OCG_SANITIZE_JOBS (default: nproc) build and test jobs.
EOF
}

SMOKE=0
MODE=
while [ $# -gt 0 ]; do
  case $1 in
    -h | --help) usage; exit 0 ;;
    --smoke) SMOKE=1 ;;
    address | undefined | thread) [ -z "$MODE" ] || { usage >&2; exit 2; }; MODE=$1 ;;
    *) echo "sanitize.sh: unknown argument '$1' (want address, undefined or thread; see --help)" >&2; exit 2 ;;
  esac
  shift
done
[ -n "$MODE" ] || { usage >&2; exit 2; }
[ "$SMOKE" -eq 0 ] || [ "$MODE" = address ] || {
  echo "sanitize.sh: --smoke goes with 'address'" >&2; exit 2; }

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
PARENT=${OCG_SANITIZE_ROOT:-$ROOT}
JOBS=${OCG_SANITIZE_JOBS:-$(nproc 2>/dev/null || echo 2)}
SUPPRESSIONS=$ROOT/tools/sanitize
START=$(date +%s)

case $MODE in
  address)
    # UndefinedBehaviorSanitizer comes along (as usual): it costs little beside ASan, and
    # one build on 2 cores instead of two.
    FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=all"
    BUILD=$PARENT/build-asan ;;
  undefined) FLAGS="-fsanitize=undefined -fno-sanitize-recover=all"; BUILD=$PARENT/build-ubsan ;;
  thread) FLAGS="-fsanitize=thread"; BUILD=$PARENT/build-tsan ;;
esac
FLAGS="$FLAGS -fno-omit-frame-pointer -g"
LOGS=$BUILD/sanitizer-logs

# halt_on_error: the first report ends the program, so no test can pass over it. Reports go
# to files (log_path) rather than stderr so that a report from a program a test expects to
# fail (tools_test.sh checks error exits) is still seen: the script fails if any file exists.
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1:log_path=$LOGS/asan"
# LeakSanitizer: leaks inside third-party libraries only (see the file for why).
export LSAN_OPTIONS="suppressions=$SUPPRESSIONS/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:log_path=$LOGS/ubsan"
export TSAN_OPTIONS="suppressions=$SUPPRESSIONS/tsan.supp:halt_on_error=1:second_deadlock_stack=1:history_size=4:log_path=$LOGS/tsan"
# OpenCV runs parallel_for_ on TBB's thread pool, which is not built with ThreadSanitizer:
# its synchronization is invisible and would be reported as races inside OpenCV. One
# OpenCV thread makes parallel_for_ run the body on the caller, so every thread TSan sees
# is one of ours. (Ceres already runs with num_threads = 1, see src/optim/solver_options.cc.)
export OPENCV_FOR_THREADS_NUM=1
# The same for Mesa's llvmpipe (OSMesa renders the generator's images and the snapshots):
# its rasterizer threads raced on its own mutexes in TSan's eyes (ocg_synth, first run).
# No rasterizer thread: llvmpipe draws on the calling thread.
export LP_NUM_THREADS=0
# OpenMP (libgomp, not instrumented), which CHOLMOD uses under Ceres's sparse solver, is
# covered by a suppression instead: CHOLMOD asks for its threads explicitly (tsan.supp).

# The same flags through the environment too: install_test.sh configures a consumer of the
# installed (sanitized) libraries, and a fresh CMake configure reads CXXFLAGS and LDFLAGS.
export CXXFLAGS="$FLAGS" LDFLAGS="$FLAGS"

LAUNCHER=()
command -v ccache >/dev/null 2>&1 &&
  LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
GENERATOR=()
[ -f "$BUILD/CMakeCache.txt" ] || { command -v ninja >/dev/null 2>&1 && GENERATOR=(-G Ninja); }

echo "== configure $MODE$([ "$SMOKE" -eq 1 ] && echo ' smoke') ($FLAGS) in $BUILD"
mkdir -p "$BUILD"
# Warnings are not errors here: gcc's -O1 with sanitizers warns about code it instruments
# (-Wmaybe-uninitialized, -Wstringop-overflow) where the normal build is clean.
# No Python module: a sanitized extension cannot be loaded by the uninstrumented python3
# (the sanitizer runtime must come first in the process); its C++ underneath is tested here.
cmake -S "$ROOT" -B "$BUILD" "${GENERATOR[@]}" "${LAUNCHER[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER=g++ -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" \
  -DCMAKE_CXX_FLAGS="$FLAGS" -DCMAKE_EXE_LINKER_FLAGS="$FLAGS" -DCMAKE_SHARED_LINKER_FLAGS="$FLAGS" \
  -DOCG_WERROR=OFF -DOCG_BUILD_BENCH=OFF -DOCG_BUILD_PYTHON=OFF >"$BUILD/configure.log" 2>&1 ||
  { cat "$BUILD/configure.log"; exit 1; }

# The smoke: the OCG (its thread included); few modules, fast tests. The input readers were
# in it too; they run under ASan and UBSan in fuzz_smoke, and building io_test with ASan
# took about two minutes of the suite's 25 on 2 cores.
SMOKE_TESTS=(ocg_test)
TARGETS=()
[ "$SMOKE" -eq 1 ] && TARGETS=(--target "${SMOKE_TESTS[@]}")
[ "$MODE" = thread ] && TARGETS=(--target ocg_test ocg_synth ocg_slam)
echo "== build ($JOBS jobs)"
BUILD_START=$(date +%s)
cmake --build "$BUILD" --parallel "$JOBS" "${TARGETS[@]}"
echo "== built in $(($(date +%s) - BUILD_START)) s"

rm -rf "$LOGS"
mkdir -p "$LOGS"
TEST_START=$(date +%s)
status=0
cd "$BUILD"
case "$MODE:$SMOKE" in
  address:1)
    # Differential.* compares the OCG with its naive reference on long random streams
    # (minutes under ASan); the other ocg tests run the same graph code, the full run all.
    for test in "${SMOKE_TESTS[@]}"; do
      OCG_SOURCE_DIR=$ROOT "./tests/$test" --gtest_brief=1 --gtest_filter=-Differential.* ||
        status=1
    done ;;
  thread:0)
    # The unit tests that start threads.
    ctest --output-on-failure --parallel "$JOBS" --timeout 1800 -R "^OcgManager\." ||
      status=$?
    # End to end, threaded: the smoke sequence's loop (the camera is back at its start by
    # frame 250) with objects, so local mapping, loop closing, its global bundle adjustment
    # and the OCG all run on their threads while tracking runs on this one.
    WORK=$BUILD/tsan-run
    rm -rf "$WORK"
    ./tools/ocg_synth --preset smoke --frames 300 --out "$WORK/smoke" --log-level warn >/dev/null
    { cat "$WORK/smoke/camera.yaml"; printf 'System:\n  sequential: false\n'; } >"$WORK/threaded.yaml"
    echo "== threaded ocg_slam run (300 frames, loop closing, objects)"
    if ./tools/ocg_slam run --settings "$WORK/threaded.yaml" --sequence "$WORK/smoke" \
      --detections "$WORK/smoke/detections" --snapshots none --out "$WORK/out" --log-level warn; then
      python3 - "$WORK/out/run.json" <<'PY' || status=1
import json, sys
run = json.load(open(sys.argv[1]))
loops = len(run["loop_closing"]["loops"])
merged = run["loop_closing"]["global_adjustments"]
print(f"threaded run: mode {run['mode']}, {loops} loop(s), {merged} global adjustment(s) merged")
# Without a closed loop and a merged adjustment their threads did no work worth checking.
sys.exit(0 if run["mode"] == "threaded" and loops >= 1 and merged >= 1 else 1)
PY
    else
      status=1
    fi ;;
  *)
    ctest --output-on-failure --parallel "$JOBS" --timeout 3600 || status=$? ;;
esac
echo "== tests ran in $(($(date +%s) - TEST_START)) s"

# gcc's UBSan inside an ASan build (address mode) prints to stderr whatever log_path says:
# look for its reports in what the tests printed too. (undefined mode writes files.)
if [ -f Testing/Temporary/LastTest.log ] && grep -q "runtime error:" Testing/Temporary/LastTest.log; then
  grep -B2 -A12 "runtime error:" Testing/Temporary/LastTest.log >"$LOGS/ubsan-in-test-output"
fi
reports=$(find "$LOGS" -type f | sort)
if [ -n "$reports" ]; then
  echo "== $(echo "$reports" | wc -l) sanitizer report(s):"
  for report in $reports; do
    echo "---- $report"
    cat "$report"
  done
  status=1
fi
echo "== $MODE$([ "$SMOKE" -eq 1 ] && echo ' smoke'): $([ "$status" -eq 0 ] && echo clean || echo FAILED) in $(($(date +%s) - START)) s"
exit "$status"
