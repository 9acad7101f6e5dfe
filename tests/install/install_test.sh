#!/usr/bin/env bash
# Installs the built project into a temporary prefix and builds a consumer against it.
#   install_test.sh <build folder> <source folder> [python3 interpreter, when the Python
#   module is built]
set -euo pipefail
BUILD=$1
SRC=$2
PYTHON=${3:-}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cmake --install "$BUILD" --prefix "$WORK/prefix" >/dev/null
cmake -S "$SRC/tests/install/consumer" -B "$WORK/build" -DCMAKE_PREFIX_PATH="$WORK/prefix" >"$WORK/log" 2>&1 || {
  cat "$WORK/log"; exit 1; }
cmake --build "$WORK/build" >>"$WORK/log" 2>&1 || { cat "$WORK/log"; exit 1; }
"$WORK/build/consumer"
test -x "$WORK/prefix/bin/ocg_replay"
test -x "$WORK/prefix/bin/ocg_plot_ate.py"
# ocg_batch finds its workflow in share/ocg/eval and the tools beside itself.
"$WORK/prefix/bin/ocg_batch" --help >/dev/null
printf 'out: %s\nsequences: [{preset: smoke, frames: 5}]\n' "$WORK/batch" >"$WORK/batch.yaml"
"$WORK/prefix/bin/ocg_batch" "$WORK/batch.yaml" --dry-run >"$WORK/log" 2>&1 || { cat "$WORK/log"; exit 1; }
grep -q "\"tools\": \"$WORK/prefix/bin\"" "$WORK/batch/batch.json" || { cat "$WORK/batch/batch.json"; exit 1; }
if [ -n "$PYTHON" ]; then
  # The module from the prefix alone (not the build folder), as a user imports it.
  PACKAGES=$(echo "$WORK"/prefix/lib/python3*/dist-packages)
  test -f "$PACKAGES/ocg/__init__.py"
  (cd "$WORK" && PYTHONPATH=$PACKAGES "$PYTHON" -c \
    "import ocg, sys; assert ocg.__file__.startswith('$WORK/prefix'), ocg.__file__; ocg.ChangeDetector(ocg.OcgOptions(mode='improved'))")
  echo "2 passed, 0 failed"
else
  echo "1 passed, 0 failed"
fi
