#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (AddressSanitizer + UndefinedBehaviorSanitizer
# on everything) in a build folder of their own and runs each for SECONDS.
set -euo pipefail

usage() {
  cat <<'USAGE'
Usage: tools/fuzz.sh [SECONDS] [--jobs N] [--only NAME[,NAME...]] [--exclude NAME[,NAME...]]
                    [--tests NAME[,NAME...]] [--build-dir DIR]

Builds every fuzz target of fuzz/targets.txt (clang 14, libFuzzer, address and undefined
sanitizers) and runs each for SECONDS (default 600), N at a time (default 1), then prints
one line per target: runs, execs/s and the result. --only keeps the named targets,
--exclude leaves them out; only the targets kept are built (with the libraries they need:
`settings` needs the whole library, the others a few modules). --tests also builds the
named test programs of tests/ (e.g. ocg_test) in the same build, so under the same
sanitizers, and runs them first: a failing test or a sanitizer report fails the run. The
suite's fuzz_smoke does so with ocg_test, the sanitizer smoke sharing the fuzzers' build
(tools/sanitize.sh runs the whole suite under gcc's sanitizers).

Seeds: fuzz/seeds/<target>/ (committed), tests/data, config/ and, when present,
../shared/data. Inputs the fuzzer finds interesting go to BUILD/corpus/<target>/ and are
reused by the next run. A finding (crash, unexpected exception, leak, timeout, out of
memory) leaves its input in BUILD/findings/<target>/ and the log in BUILD/logs/<target>.log;
reproduce it with: BUILD/fuzz/ocg_fuzz_<target> FILE

Limits per input: -max_len from fuzz/targets.txt, -timeout=10 s, -rss_limit_mb=2048
(also the largest single allocation).

Build folder: --build-dir, else $OCG_FUZZ_BUILD_DIR, else build-fuzz/ in the source tree.
Exit status: 0 when nothing was found, 1 on any finding or failing test, 2 on a usage or
build error.
USAGE
}

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${OCG_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}
SECONDS_PER_TARGET=600
JOBS=1
ONLY=""
EXCLUDE=""
TESTS=""
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --jobs) JOBS=${2:?--jobs needs a number}; shift 2 ;;
    --only) ONLY=${2:?--only needs target names}; shift 2 ;;
    --exclude) EXCLUDE=${2:?--exclude needs target names}; shift 2 ;;
    --tests) TESTS=${2:?--tests needs test program names}; shift 2 ;;
    --build-dir) BUILD=${2:?--build-dir needs a folder}; shift 2 ;;
    *)
      if [[ "$1" =~ ^[0-9]+$ ]] && [ "$1" -gt 0 ]; then
        SECONDS_PER_TARGET=$1; shift
      else
        echo "fuzz.sh: unknown argument '$1' (SECONDS must be a positive whole number)" >&2
        usage >&2; exit 2
      fi ;;
  esac
done
[[ "$JOBS" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: --jobs must be a positive number, got '$JOBS'" >&2; exit 2; }
mkdir -p "$BUILD"
BUILD=$(cd "$BUILD" && pwd)

for tool in clang clang++; do
  command -v "$tool" >/dev/null 2>&1 || {
    echo "fuzz.sh: '$tool' not found: run tools/install_deps.sh (Debian packages clang, libclang-rt-14-dev)" >&2
    exit 2
  }
done

# A misspelt name would silently fuzz everything or nothing it was meant to.
for name in ${ONLY//,/ } ${EXCLUDE//,/ }; do
  grep -qE "^$name +" "$ROOT/fuzz/targets.txt" ||
    { echo "fuzz.sh: no fuzz target '$name' (see fuzz/targets.txt)" >&2; exit 2; }
done
for test in ${TESTS//,/ }; do
  grep -qE "^ocg_add_test\($test( |$)" "$ROOT/tests/CMakeLists.txt" ||
    { echo "fuzz.sh: no test program '$test' (see ocg_add_test in tests/CMakeLists.txt)" >&2; exit 2; }
done

# name max_len, from the one list CMake also builds from.
TARGETS=()
declare -A MAX_LEN
while read -r name _library max_len; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  if [ -n "$ONLY" ] && [[ ",$ONLY," != *",$name,"* ]]; then continue; fi
  if [[ ",$EXCLUDE," == *",$name,"* ]]; then continue; fi
  TARGETS+=("$name")
  MAX_LEN[$name]=$max_len
done <"$ROOT/fuzz/targets.txt"
[ ${#TARGETS[@]} -gt 0 ] || { echo "fuzz.sh: no target left by --only '$ONLY' --exclude '$EXCLUDE' (see fuzz/targets.txt)" >&2; exit 2; }

LAUNCHER=()
command -v ccache >/dev/null 2>&1 &&
  LAUNCHER=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
GENERATOR=()
[ -f "$BUILD/CMakeCache.txt" ] || { command -v ninja >/dev/null 2>&1 && GENERATOR=(-G Ninja); }
echo "== configure ($BUILD)"
# Debug keeps assert() and Eigen's index checks; -O1 keeps the fuzzer fast enough; line tables
# (not full debug info) give reports their file:line at a third of the compile time. Warnings
# are not errors here: clang warns about things gcc (the -Werror build of tools/test.sh) does not.
cmake -S "$ROOT" -B "$BUILD" "${GENERATOR[@]}" "${LAUNCHER[@]}" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-gline-tables-only -O1" \
  -DOCG_FUZZ=ON -DOCG_WERROR=OFF -DOCG_BUILD_TESTS=ON -DOCG_BUILD_BENCH=OFF -DOCG_BUILD_TOOLS=ON \
  -DOCG_BUILD_PYTHON=OFF \
  >"$BUILD/configure.log" 2>&1 || { cat "$BUILD/configure.log"; exit 2; }
echo "== build ($(nproc 2>/dev/null || echo 2) jobs)"
BUILD_START=$(date +%s)
TEST_PROGRAMS=(${TESTS//,/ })
cmake --build "$BUILD" --target "${TARGETS[@]/#/ocg_fuzz_}" "${TEST_PROGRAMS[@]}" --parallel "$(nproc 2>/dev/null || echo 2)" \
  >"$BUILD/build.log" 2>&1 || { tail -n 60 "$BUILD/build.log"; echo "fuzz.sh: build failed, log: $BUILD/build.log" >&2; exit 2; }
echo "   built in $(( $(date +%s) - BUILD_START )) s"

# The test programs first (tools/sanitize.sh's smoke, on clang's build): a report ends the
# program (halt_on_error, -fno-sanitize-recover) and fails the run like a failing test.
# Differential.* compares the OCG with its naive reference on long random streams (minutes
# under ASan); the other tests run the same graph code.
for test in "${TEST_PROGRAMS[@]}"; do
  echo "== $test (address, undefined)"
  TEST_START=$(date +%s)
  (cd "$BUILD/tests" &&
    ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1 \
    LSAN_OPTIONS="suppressions=$ROOT/tools/sanitize/lsan.supp:print_suppressions=0" \
    UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 OCG_SOURCE_DIR=$ROOT \
      "./$test" --gtest_brief=1 --gtest_filter=-Differential.*) ||
    { echo "fuzz.sh: $test failed under the sanitizers (its output above)" >&2; exit 1; }
  echo "   ran in $(($(date +%s) - TEST_START)) s"
done

# Seeds beyond fuzz/seeds: the real files the readers are made for, where they exist.
SHARED=${OCG_SHARED_DATA:-$ROOT/../shared/data}
extra_seeds() {
  local name=$1 out=$2
  mkdir -p "$out"
  case "$name" in
    settings|settings_file)
      # settings_file parses the same files: it shares the committed seeds of settings.
      [ "$name" = settings_file ] && cp "$ROOT"/fuzz/seeds/settings/* "$out"/
      cp "$ROOT"/config/*.yaml "$out"/ 2>/dev/null || true
      [ -d "$SHARED" ] && find "$SHARED" -maxdepth 2 -name '*.yaml' -size -8k -exec cp {} "$out"/ \; ;;
    replay_jsonl)
      # Every prefix of the example stream: the fuzzer starts from valid histories.
      for n in 1 2 4 8 16; do head -n "$n" "$ROOT/tests/data/ocg_example.jsonl" >"$out/example_$n.jsonl"; done ;;
    tum_image_list)
      [ -f "$SHARED/tum_fr3_long_office/rgb.txt" ] && head -c 4000 "$SHARED/tum_fr3_long_office/rgb.txt" >"$out/tum_rgb.txt" ;;
    trajectory_tum)
      [ -f "$SHARED/tum_fr3_long_office/groundtruth.txt" ] && head -c 4000 "$SHARED/tum_fr3_long_office/groundtruth.txt" >"$out/tum_gt.txt"
      [ -f "$SHARED/euroc_v101_micro/groundtruth_body_tum.txt" ] && head -c 4000 "$SHARED/euroc_v101_micro/groundtruth_body_tum.txt" >"$out/euroc_gt.txt" ;;
    euroc_data_csv)
      [ -f "$SHARED/euroc_v101_micro/mav0/cam0/data.csv" ] && head -c 4000 "$SHARED/euroc_v101_micro/mav0/cam0/data.csv" >"$out/data.csv" ;;
    euroc_sensor_yaml)
      [ -f "$SHARED/euroc_v101_micro/mav0/cam0/sensor.yaml" ] && cp "$SHARED/euroc_v101_micro/mav0/cam0/sensor.yaml" "$out"/ ;;
    detections_text)
      # The first byte of an input chooses strict (even) or lenient (odd) reading.
      if [ -d "$SHARED/tum_fr3_long_office/detections" ]; then
        # A glob, not `ls | head`: under pipefail, head exiting early fails the pipe.
        local i=0 files=("$SHARED/tum_fr3_long_office/detections"/*)
        for file in "${files[@]:0:20}"; do
          { printf 's'; cat "$file"; } >"$out/real_$i.txt"
          i=$((i + 1))
        done
      fi ;;
  esac
  return 0
}

# Values of libFuzzer's final statistics.
stat() { sed -n "s/^stat::$2: *//p" "$1" | tail -n 1; }

run_target() {
  local name=$1
  local binary="$BUILD/fuzz/ocg_fuzz_$name" corpus="$BUILD/corpus/$name"
  local findings="$BUILD/findings/$name" extra="$BUILD/seeds_extra/$name" log="$BUILD/logs/$name.log"
  mkdir -p "$corpus" "$findings" "$BUILD/logs"
  extra_seeds "$name" "$extra"
  local seeds=("$ROOT/fuzz/seeds/$name")
  [ -d "${seeds[0]}" ] || seeds=()
  local status=0
  ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0} \
  UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
    "$binary" -max_total_time="$SECONDS_PER_TARGET" -max_len="${MAX_LEN[$name]}" -timeout=10 \
    -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$findings/" "$corpus" "${seeds[@]}" "$extra" >"$log" 2>&1 || status=$?
  local runs speed result
  runs=$(stat "$log" number_of_executed_units)
  speed=$(stat "$log" average_exec_per_sec)
  if [ "$status" -eq 0 ]; then
    result=ok
  else
    local artifact
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n 1)
    local kind
    kind=$(grep -m1 -oE "ERROR: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|libFuzzer): [a-zA-Z-]+|runtime error: .*|uncaught exception|out-of-memory|timeout" "$log" | head -c 120 || true)
    result="FINDING (${kind:-exit $status}): ${artifact:-no input saved}, log $log"
  fi
  printf '%-20s runs %-10s execs/s %-7s %s\n' "$name" "${runs:-?}" "${speed:-?}" "$result" \
    >"$BUILD/logs/$name.summary"
  [ "$status" -eq 0 ]
}

echo "== fuzz ${#TARGETS[@]} target(s), $SECONDS_PER_TARGET s each, $JOBS at a time"
rm -f "$BUILD"/logs/*.summary
pids=()
names=()
for name in "${TARGETS[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
  run_target "$name" &
  pids+=($!)
  names+=("$name")
done
failed=0
for i in "${!pids[@]}"; do
  wait "${pids[$i]}" || failed=$((failed + 1))
done
echo "== results"
for name in "${names[@]}"; do cat "$BUILD/logs/$name.summary"; done
if [ "$failed" -gt 0 ]; then
  echo "fuzz.sh: $failed target(s) found something; inputs under $BUILD/findings/" >&2
  exit 1
fi
echo "fuzz.sh: nothing found"
