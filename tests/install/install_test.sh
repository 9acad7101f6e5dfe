#!/usr/bin/env bash
# Installs the built project into a temporary prefix and builds a consumer against it.
#   install_test.sh <build folder> <source folder>
set -euo pipefail
BUILD=$1
SRC=$2
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cmake --install "$BUILD" --prefix "$WORK/prefix" >/dev/null
cmake -S "$SRC/tests/install/consumer" -B "$WORK/build" -DCMAKE_PREFIX_PATH="$WORK/prefix" >"$WORK/log" 2>&1 || {
  cat "$WORK/log"; exit 1; }
cmake --build "$WORK/build" >>"$WORK/log" 2>&1 || { cat "$WORK/log"; exit 1; }
"$WORK/build/consumer"
test -x "$WORK/prefix/bin/ocg_replay"
echo "1 passed, 0 failed"
