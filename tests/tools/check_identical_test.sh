#!/usr/bin/env bash
# tools/check_identical.py, short: the smoke preset's first 30 frames recorded and compared
# with the same build give identical outputs (exit 0); a changed output is reported with
# the file, its first differing line and, for JSON, the first differing key (exit 1); bad
# arguments are one-line errors (exit 2). Map files are left out of the verdict: they do
# not repeat from run to run yet (their BoW entries carry uninitialized padding bytes).
#   check_identical_test.sh <build folder> <source folder>
set -euo pipefail
BUILD=$1
SOURCE=$2
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAILED: $*"; exit 1; }
CHECK="python3 $SOURCE/tools/check_identical.py"

$CHECK record "$BUILD" "$WORK/base" --only preset_smoke --frames 30 >"$WORK/record.log" 2>&1 \
  || { cat "$WORK/record.log"; fail "record"; }
[ -f "$WORK/base/manifest.json" ] || fail "no manifest written"
[ -f "$WORK/base/before/preset_smoke/improved/objects.json" ] || fail "no objects.json kept"
$CHECK compare "$BUILD" "$WORK/base" --ignore '*.ocgmap' >"$WORK/compare.log" 2>&1 \
  || { cat "$WORK/compare.log"; fail "the same build compared differs"; }
grep -q "ALL IDENTICAL" "$WORK/compare.log" || fail "no verdict printed"
grep -q "improved/changes.json *identical" "$WORK/compare.log" || fail "no per-file line"
echo "passed: record and compare with the same build: identical"

cp -r "$WORK/base/after/preset_smoke" "$WORK/changed"
sed -i '2s/"format"/ "format"/' "$WORK/changed/paper/objects.json"
python3 - "$WORK/changed/improved/objects.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["up"][0] += 0.5
json.dump(d, open(sys.argv[1], "w"), indent=2)
PY
status=0
$CHECK diff "$WORK/base/after/preset_smoke" "$WORK/changed" --ignore '*.ocgmap' >"$WORK/diff.log" 2>&1 || status=$?
cat "$WORK/diff.log"
[ "$status" -eq 1 ] || fail "changed outputs gave exit status $status (want 1)"
grep -q "paper/objects.json *differs: .* first at line 2" "$WORK/diff.log" || fail "no first differing line"
grep -q 'first JSON difference at \$.up\[0\]' "$WORK/diff.log" || fail "no first differing JSON key"
grep -q "improved/changes.json *identical" "$WORK/diff.log" || fail "an unchanged file reported as changed"
echo "passed: changed outputs reported file by file"

status=0
$CHECK compare "$BUILD" "$WORK/nothing" >"$WORK/bad.log" 2>&1 || status=$?
[ "$status" -eq 2 ] && grep -q "manifest.json not found" "$WORK/bad.log" || fail "no clear error for a missing baseline"
status=0
$CHECK record "$BUILD" "$WORK/other" --only preset_nothing >"$WORK/bad.log" 2>&1 || status=$?
[ "$status" -eq 2 ] && grep -q "unknown run(s) preset_nothing" "$WORK/bad.log" || fail "no clear error for an unknown run"
echo "passed: bad arguments are one-line errors"
