"""ocg.Detector and ocg.detect_images against ocg_detect, on a tiny YOLOv8 model built at
test time (python3-onnx), and the default model on a real frame when both are there."""
import os
import subprocess
import sys

import numpy as np
import pytest

import ocg

HERE = os.path.dirname(os.path.abspath(__file__))


@pytest.fixture(scope="module")
def tiny_model(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("tiny") / "yolov8.onnx")
    made = subprocess.run(["/usr/bin/python3", os.path.join(HERE, "make_tiny_detector.py"),
                           "yolov8", path], capture_output=True)
    if made.returncode != 0:
        pytest.skip("needs Debian's python3-onnx to build the tiny model")
    return path


def test_detect_gives_the_rows_track_takes(tiny_model):
    detector = ocg.Detector(tiny_model)
    assert detector.description == "YOLOv8, 80 classes, input 128x128"
    rows = detector.detect(np.zeros((256, 256, 3), np.uint8))
    # Every anchor outputs the same box (48, 48, 32, 32) at the input, doubled in the image.
    np.testing.assert_allclose(rows, [[5, 96, 96, 64, 64, 0.9]], atol=1e-4)
    assert detector.detect(np.zeros((256, 256), np.uint8)).shape == (1, 6)  # grey too
    with pytest.raises(ValueError, match="uint8 array"):
        detector.detect(np.zeros((4, 4, 2), np.uint8))


def test_options_and_missing_model_are_clear_errors(tiny_model):
    with pytest.raises(ValueError, match="tile"):
        ocg.Detector(tiny_model, tile="sometimes")
    with pytest.raises(ValueError, match="score_threshold"):
        ocg.Detector(tiny_model, score=2.0)
    with pytest.raises(ocg.FileError, match="missing.onnx"):
        ocg.Detector("/nonexistent/missing.onnx")


def test_detect_images_writes_what_ocg_detect_writes(tiny_model, tmp_path):
    images = tmp_path / "images"
    images.mkdir()
    for name in ("1.5", "2.5"):
        _write_png(images / f"{name}.png", 128, 128)
    summary = ocg.detect_images(str(images), str(tmp_path / "py"), model=tiny_model, json=True)
    assert summary["images"] == 2 and summary["boxes"] == 2
    assert summary["boxes_per_class"] == {5: 2}
    tools = os.environ.get("OCG_TOOLS")
    if tools:
        subprocess.run([os.path.join(tools, "ocg_detect"), "--images", str(images), "--out",
                        str(tmp_path / "cli"), "--model", tiny_model, "--json"], check=True,
                       capture_output=True)
        for name in ("1.5.txt", "2.5.txt"):
            assert (tmp_path / "py" / name).read_text() == (tmp_path / "cli" / name).read_text()
    assert (tmp_path / "py" / "detections.json").exists()


def _write_png(path, width, height):
    import struct
    import zlib
    raw = b"".join(b"\x00" + b"\x50" * (3 * width) for _ in range(height))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" +
                     chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                     chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
