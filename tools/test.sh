#!/usr/bin/env bash
# Installs what is missing, builds OCG-SLAM (warnings are errors), and runs every test.
# Usage: tools/test.sh            (build folder: build/, or $OCG_BUILD_DIR)
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${OCG_BUILD_DIR:-$ROOT/build}
JOBS=$(nproc 2>/dev/null || echo 2)
START=$(date +%s)

"$ROOT/tools/install_deps.sh"

# Ninja when available for a new build folder; an existing folder keeps its generator.
GENERATOR=()
[ -f "$BUILD/CMakeCache.txt" ] || { command -v ninja >/dev/null 2>&1 && GENERATOR=(-G Ninja); }
echo "== configure ($BUILD)"
mkdir -p "$BUILD"
cmake -S "$ROOT" -B "$BUILD" "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE=Release -DOCG_WERROR=ON \
  >"$BUILD/configure.log" 2>&1 || { cat "$BUILD/configure.log"; exit 1; }
echo "== build ($JOBS jobs)"
cmake --build "$BUILD" --parallel "$JOBS"
echo "== test"
cd "$BUILD"
ctest --output-on-failure --parallel "$JOBS" --timeout 900
echo "== done in $(( $(date +%s) - START )) s"
