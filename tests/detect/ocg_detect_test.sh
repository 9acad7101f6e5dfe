#!/usr/bin/env bash
# ocg_detect end to end with a tiny YOLOv8-shaped model built at test time (the real
# model is not needed): files written and readable by ocg_convert_detections, --json,
# --help, and clear errors before any work.
set -euo pipefail
TOOLS="$1"
SOURCE_DIR="$2"
WORK="$(mktemp -d)"
trap 'rm -rf "${WORK}"' EXIT
fail() { echo "FAIL: $1"; [ -f "${2:-}" ] && cat "$2"; exit 1; }

if ! /usr/bin/python3 "${SOURCE_DIR}/tests/detect/make_tiny_detector.py" yolov8 "${WORK}/tiny.onnx" 2>/dev/null; then
  echo "SKIP: needs Debian's python3-onnx to build the tiny model"; exit 0
fi
/usr/bin/python3 - "${WORK}" <<'PY'
import sys, zlib, struct
def png(path, w, h):
    raw = b"".join(b"\x00" + bytes([40, 80, 120]) * w for _ in range(h))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                           + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
import os
os.makedirs(sys.argv[1] + "/seq/rgb")
for t in ("1.000000", "1.033000"):
    png(f"{sys.argv[1]}/seq/rgb/{t}.png", 256, 256)
open(sys.argv[1] + "/seq/rgb.txt", "w").write("# test\n1.000000 rgb/1.000000.png\n1.033000 rgb/1.033000.png\n")
PY

help=$("${TOOLS}/ocg_detect" --help)
grep -q -- "--tile" <<<"${help}" || fail "--help lacks --tile"

"${TOOLS}/ocg_detect" --images "${WORK}/seq/rgb.txt" --out "${WORK}/det" --model "${WORK}/tiny.onnx" \
  --json > "${WORK}/out" 2>&1 || fail "a run on two frames failed" "${WORK}/out"
grep -q "YOLOv8, 80 classes, input 128x128" "${WORK}/out" || fail "the model is not described" "${WORK}/out"
grep -q "2 boxes in 2 images" "${WORK}/out" || fail "wrong summary" "${WORK}/out"
[ "$(cat "${WORK}/det/1.033000.txt")" = "5 96 96 64 64 0.900000" ] ||
  fail "unexpected detection file" "${WORK}/det/1.033000.txt"
[ -f "${WORK}/det/detections.json" ] || fail "--json wrote no detections.json"
"${TOOLS}/ocg_convert_detections" --from "${WORK}/det" --to "${WORK}/back.json" > /dev/null ||
  fail "the product's reader refuses the files"

# Errors before any work: a missing list, a model that is not ONNX; nothing written.
if "${TOOLS}/ocg_detect" --images "${WORK}/nothing.txt" --out "${WORK}/det2" \
    --model "${WORK}/tiny.onnx" > "${WORK}/err1" 2>&1; then fail "a missing list was accepted"; fi
grep -q "nothing.txt" "${WORK}/err1" || fail "the error does not name the list" "${WORK}/err1"
echo "not a model" > "${WORK}/bad.onnx"
if "${TOOLS}/ocg_detect" --images "${WORK}/seq" --out "${WORK}/det3" --model "${WORK}/bad.onnx" \
    > "${WORK}/err2" 2>&1; then fail "a broken model was accepted"; fi
grep -q "bad.onnx" "${WORK}/err2" || fail "the error does not name the model" "${WORK}/err2"
[ ! -e "${WORK}/det3" ] || fail "a failed run left an output folder"
# A frame list naming a missing image fails before the first image is processed.
cp "${WORK}/seq/rgb.txt" "${WORK}/seq/rgb_missing.txt"
echo "1.066000 rgb/1.066000.png" >> "${WORK}/seq/rgb_missing.txt"
if "${TOOLS}/ocg_detect" --images "${WORK}/seq/rgb_missing.txt" --out "${WORK}/det4" \
    --model "${WORK}/tiny.onnx" > "${WORK}/err3" 2>&1; then fail "a missing image was accepted"; fi
grep -q "1.066000.png" "${WORK}/err3" || fail "the error does not name the image" "${WORK}/err3"
[ ! -e "${WORK}/det4" ] || fail "a run refused at start left an output folder"
echo "ocg_detect end to end: OK"
