"""ocg.ObjectSlam: the smoke sequence fed from Python gives what `ocg_slam run` writes, and
the errors a Python caller can make are named."""
import filecmp
import json
import os
import subprocess
import sys
import threading

import numpy as np
import pytest

import ocg
from conftest import run_tool

FRAMES = 80


@pytest.fixture(scope="module")
def smoke(tools, tmp_path_factory):
    """A generated smoke sequence with detections, and the tool's run on it."""
    work = tmp_path_factory.mktemp("object_slam")
    sequence = str(work / "smoke")
    run_tool(tools, "ocg_synth", "--preset", "smoke", "--frames", str(FRAMES), "--out", sequence,
             "--keyframe-interval", "0", "--log-level", "warn")
    tool_out = str(work / "tool")
    run_tool(tools, "ocg_slam", "run", "--settings", sequence + "/camera.yaml", "--sequence", sequence,
             "--detections", sequence + "/detections", "--snapshots", "none", "--out", tool_out,
             "--log-level", "warn")
    return sequence, tool_out


def frames(sequence):
    """(timestamp, image path, (N, 6) detections) of each frame, from rgb.txt."""
    with open(os.path.join(sequence, "rgb.txt")) as listing:
        for line in listing:
            if line.startswith("#") or not line.strip():
                continue
            stamp, image = line.split()
            boxes = os.path.join(sequence, "detections", stamp + ".txt")
            detections = np.loadtxt(boxes, ndmin=2) if os.path.exists(boxes) else np.zeros((0, 6))
            yield float(stamp), os.path.join(sequence, image), detections


def test_smoke_sequence_gives_the_tools_trajectory(smoke, tmp_path):
    sequence, tool_out = smoke
    slam = ocg.ObjectSlam(sequence + "/camera.yaml")
    poses = []
    for timestamp, image, detections in frames(sequence):
        T_cw = slam.track(ocg.read_image(image), timestamp, detections, image_path=image)
        if T_cw is not None:
            assert T_cw.shape == (4, 4) and T_cw.dtype == np.float64
            np.testing.assert_allclose(T_cw[:3, :3] @ T_cw[:3, :3].T, np.eye(3), atol=1e-9)
            np.testing.assert_array_equal(T_cw[3], [0, 0, 0, 1])
        poses.append(T_cw)
    assert sum(pose is not None for pose in poses) > FRAMES // 2
    slam.shutdown()
    slam.shutdown()  # safe twice

    # The keyframe trajectory equals the tool's (written with 9 decimals).
    ours = slam.keyframe_trajectory()
    tools = ocg.read_tum_trajectory(os.path.join(tool_out, "KeyFrameTrajectory.txt"))
    assert ours.shape == tools.shape and ours.shape[0] >= 5
    np.testing.assert_allclose(ours, tools, rtol=0, atol=1e-8)
    # And every file save() writes is the tool's, byte for byte.
    report = slam.save(tmp_path)
    for name in ["KeyFrameTrajectory.txt", "CameraTrajectory.txt", "map_points.ply", "objects.json",
                 "changes.json", "ocg.json", "ocg_observations.jsonl"]:
        assert filecmp.cmp(tmp_path / name, os.path.join(tool_out, name), shallow=False), name
    assert report["frames"] == FRAMES
    # The objects' colours come from the same keyframe images as the tool's.
    tool_report = json.load(open(os.path.join(tool_out, "run.json")))
    assert report["objects"]["colour_signatures"]["sightings"] > 0
    assert report["objects"]["colour_signatures"] == tool_report["objects"]["colour_signatures"]
    # The readers as dicts: what objects.json and changes.json hold.
    objects = slam.objects()
    assert isinstance(objects, dict) and objects == json.load(open(tmp_path / "objects.json"))
    assert slam.changes() == json.load(open(tmp_path / "changes.json"))

    with pytest.raises(RuntimeError, match="shut down"):
        slam.track(ocg.read_image(next(frames(sequence))[1]), 1e9, None)


def test_colour_frames_and_a_thread_of_their_own(smoke):
    """BGR frames fed from another Python thread (track releases the GIL) track along the
    grey run's path; the main thread keeps running meanwhile."""
    sequence, tool_out = smoke
    slam = ocg.ObjectSlam(sequence + "/camera.yaml", map_objects=False)
    errors = []

    def feed():
        try:
            for timestamp, image, _ in frames(sequence):
                slam.track(ocg.read_image(image, "bgr"), timestamp)
        except Exception as error:  # reported by the main thread
            errors.append(error)

    worker = threading.Thread(target=feed)
    worker.start()
    ticks = 0
    while worker.is_alive():
        ticks += 1
        worker.join(0.01)
    assert not errors, errors
    assert ticks > 1, "the main thread did not run while track() worked"
    slam.shutdown()
    tools = ocg.read_tum_trajectory(os.path.join(tool_out, "KeyFrameTrajectory.txt"))
    # OpenCV's BGR-to-grey conversion rounds otherwise than its PNG decoder's, so the
    # pixels differ by one level here and there: the same path, not the same bits.
    ours = slam.keyframe_trajectory()
    assert ours.shape[0] >= 5
    assert slam.objects() is None and slam.changes() is None
    assert ocg.ate(tools, ours, align="sim3").rmse < 0.02


def test_errors_name_what_to_fix(smoke, tmp_path):
    sequence, _ = smoke
    with pytest.raises(ocg.SettingsError, match="missing.yaml"):
        ocg.ObjectSlam(str(tmp_path / "missing.yaml"))
    with pytest.raises(ocg.FileError, match="none.ocgvoc"):
        ocg.ObjectSlam(sequence + "/camera.yaml", vocabulary=str(tmp_path / "none.ocgvoc"))
    with pytest.raises(ValueError, match="mode"):
        ocg.ObjectSlam(sequence + "/camera.yaml", mode="clever")
    slam = ocg.ObjectSlam(sequence + "/camera.yaml")
    with pytest.raises(ValueError, match="uint8"):
        slam.track(np.zeros((480, 640), np.float32), 0.0)
    with pytest.raises(ValueError, match="HxWx3"):
        slam.track(np.zeros((480, 640, 4), np.uint8), 0.0)
    with pytest.raises(ValueError, match=r"\(N, 6\)"):
        slam.track(np.zeros((480, 640), np.uint8), 0.0, np.zeros((2, 5)))
    with pytest.raises(ValueError, match="score"):
        slam.track(np.zeros((480, 640), np.uint8), 0.0, np.array([[41, 10, 10, 20, 20, 1.5]]))
    with pytest.raises(RuntimeError, match="Shutdown"):
        slam.save(tmp_path)
    with pytest.raises(ocg.FileError):
        ocg.read_image(str(tmp_path / "none.png"))
    assert slam.pose() is None


def test_map_file_continues_as_the_next_session(smoke, tmp_path):
    sequence, _ = smoke
    first = ocg.ObjectSlam(sequence + "/camera.yaml")
    assert first.session == 0
    for timestamp, image, detections in frames(sequence):
        first.track(ocg.read_image(image), timestamp, detections)
    first.shutdown()
    first.save_map(tmp_path / "a.ocgmap")
    second = ocg.ObjectSlam(sequence + "/camera.yaml", load_map=str(tmp_path / "a.ocgmap"))
    assert second.session == 1
    # The loaded map as it was saved, before any frame of the new session.
    np.testing.assert_array_equal(second.keyframe_trajectory(), first.keyframe_trajectory())
    assert second.pose() is None
    with pytest.raises(ocg.FileError, match="not an OCG-SLAM map file"):
        ocg.ObjectSlam(sequence + "/camera.yaml", load_map=sequence + "/rgb.txt")


def test_example_script_runs_the_sequence(smoke, source_dir, tmp_path):
    sequence, _ = smoke
    script = os.path.join(source_dir, "examples", "object_slam.py")
    result = subprocess.run([sys.executable, script, sequence, "--max-frames", "30", "--out",
                             str(tmp_path / "run")], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "camera at" in result.stdout and "objects" in result.stdout
    with open(tmp_path / "run" / "run.json") as run:
        assert json.load(run)["frames"] == 30
