"""ocg.ObjectSlam: the smoke sequence fed from Python gives what `ocg_slam run` writes, and
the errors a Python caller can make are named."""
import filecmp
import json
import os
import shutil
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
    states = set()
    for timestamp, image, detections in frames(sequence):
        result = slam.track(ocg.read_image(image), timestamp, detections, image_path=image)
        T_cw = result.pose
        states.add(result.state)
        assert (T_cw is not None) == (result.state == "ok")
        if T_cw is not None:
            assert T_cw.shape == (4, 4) and T_cw.dtype == np.float64
            np.testing.assert_allclose(T_cw[:3, :3] @ T_cw[:3, :3].T, np.eye(3), atol=1e-9)
            np.testing.assert_array_equal(T_cw[3], [0, 0, 0, 1])
        poses.append(T_cw)
    assert sum(pose is not None for pose in poses) > FRAMES // 2
    assert states <= {"not_initialized", "ok", "lost"} and "ok" in states
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


def test_run_with_boxes_in_memory_writes_what_the_tool_writes(smoke, tmp_path):
    """run() feeds the sequence through the tool's sequence runner (here with two images
    read ahead): boxes given as a dict in memory give the tool's files, byte for byte."""
    sequence, tool_out = smoke
    boxes = {}  # keyed by the timestamp texts of rgb.txt
    for name in os.listdir(os.path.join(sequence, "detections")):
        boxes[name[:-len(".txt")]] = np.loadtxt(os.path.join(sequence, "detections", name), ndmin=2)
    slam = ocg.ObjectSlam(sequence + "/camera.yaml")
    fed = slam.run(sequence, detections=boxes, read_ahead=2)
    assert fed["frames"] == FRAMES and not fed["stopped"]
    assert fed["reader"]["read_ahead"] == 2
    assert fed["reader"]["detections"] == "boxes in memory"
    assert fed["reader"]["detect_per_frame"]["count"] == FRAMES
    slam.shutdown()
    report = slam.save(tmp_path)
    for name in ["KeyFrameTrajectory.txt", "CameraTrajectory.txt", "map_points.ply", "objects.json",
                 "changes.json", "ocg.json", "ocg_observations.jsonl"]:
        assert filecmp.cmp(tmp_path / name, os.path.join(tool_out, name), shallow=False), name
    assert report["sequence"] == sequence and report["reader"]["read_ahead"] == 2


def test_run_errors_name_what_to_fix(smoke, tmp_path):
    sequence, _ = smoke
    slam = ocg.ObjectSlam(sequence + "/camera.yaml")
    with pytest.raises(ValueError, match="not both"):
        slam.run(sequence, detections={}, detect=True)
    with pytest.raises(ocg.FileError, match="no detector model at"):
        slam.run(sequence, detect=True, model=str(tmp_path / "none.onnx"))
    with pytest.raises(ocg.FileError, match="neither a folder"):
        slam.run(sequence, detections=tmp_path / "none")
    with pytest.raises(ocg.ParseError, match="row 0"):
        slam.run(sequence, detections={"1.0": np.array([[80, 1, 1, 2, 2, 0.5]])})


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
    with pytest.raises(ValueError, match=r"\(N, 6\).*got shape \(2, 5\): 5 columns"):
        slam.track(np.zeros((480, 640), np.uint8), 0.0, np.zeros((2, 5)))
    with pytest.raises(ValueError, match="confidence must be in"):
        slam.track(np.zeros((480, 640), np.uint8), 0.0, np.array([[41, 10, 10, 20, 20, 1.5]]))


@pytest.mark.parametrize("row, message", [
    ([500, 10, 10, 20, 20, 0.5], "row 0: class_id must be a COCO-80 index in \\[0, 79\\], got 500"),
    ([41.5, 10, 10, 20, 20, 0.5], "class_id must be a COCO-80 index"),
    ([41, np.nan, 10, 20, 20, 0.5], "x y must be finite"),
    ([41, 10, np.inf, 20, 20, 0.5], "x y must be finite"),
    ([41, 10, 10, np.nan, 20, 0.5], "width and height must be positive"),
    ([41, 10, 10, 20, np.inf, 0.5], "width and height must be positive"),
    ([41, 10, 10, 20, 20, np.nan], "confidence must be in"),
])
def test_detection_rows_a_detection_file_may_not_hold_are_refused(smoke, row, message):
    """The text reader's check, shared: ocg.ParseError (a ValueError) naming the row."""
    sequence, _ = smoke
    slam = ocg.ObjectSlam(sequence + "/camera.yaml", map_objects=False)
    image = np.zeros((480, 640), np.uint8)
    with pytest.raises(ocg.ParseError, match=message):
        slam.track(image, 0.0, np.array([row]))
    # Nothing was tracked for the refused frame: its time is still free.
    assert slam.track(image, 0.0, np.array([[41, 10, 10, 20, 20, 0.5]])).state == "not_initialized"


def test_timestamps_must_be_finite_and_increase(smoke):
    """What the frame lists' readers refuse: a NaN or infinite time, one not later."""
    sequence, _ = smoke
    slam = ocg.ObjectSlam(sequence + "/camera.yaml", map_objects=False)
    image = np.zeros((480, 640), np.uint8)
    for bad in [np.nan, np.inf, -np.inf]:
        with pytest.raises(ValueError, match="finite"):
            slam.track(image, bad)
    assert slam.track(image, 1.0).state == "not_initialized"
    with pytest.raises(ValueError, match="not later than the last frame's 1"):
        slam.track(image, 1.0)
    with pytest.raises(ValueError, match="0.5 is not later"):
        slam.track(image, 0.5)
    assert slam.track(image, 1.5).state == "not_initialized"
    # Times as TUM gives them: both named with the digits that tell them apart.
    assert slam.track(image, 1305031229.528748).state == "not_initialized"
    with pytest.raises(ValueError, match=r"1305031229\.5287\d+ is not later than the last "
                                         r"frame's 1305031229\.528748"):
        slam.track(image, 1305031229.52874)
    slam.shutdown()
    assert slam.camera_trajectory().shape[0] == 0


def test_a_colour_image_gives_the_colour_signatures_without_a_file(smoke, tmp_path):
    """The BGR pixels given to track() give the objects' colours as their file would."""
    sequence, _ = smoke
    reports = []
    for with_path in [True, False]:
        slam = ocg.ObjectSlam(sequence + "/camera.yaml")
        for timestamp, image, detections in frames(sequence):
            slam.track(ocg.read_image(image, "bgr"), timestamp, detections,
                       image_path=image if with_path else None)
        slam.shutdown()
        folder = tmp_path / ("file" if with_path else "pixels")
        folder.mkdir()
        reports.append(slam.save(folder))
    assert reports[1]["objects"]["colour_signatures"]["sightings"] > 0
    assert reports[1]["objects"]["colour_signatures"] == reports[0]["objects"]["colour_signatures"]


def test_more_errors_name_what_to_fix(smoke, tmp_path):
    sequence, _ = smoke
    slam = ocg.ObjectSlam(sequence + "/camera.yaml")
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


def test_the_module_names_the_interpreter_it_was_built_for():
    """It loads in that interpreter only: the build names it, so a user with pyenv first on
    PATH learns which one to run."""
    version = "(Python %d.%d)" % sys.version_info[:2]
    assert ocg.BUILT_FOR_PYTHON.endswith(version), ocg.BUILT_FOR_PYTHON
    assert os.path.isabs(ocg.BUILT_FOR_PYTHON.split(" ")[0])


def test_an_interpreter_without_numpy_is_told_which_one_has_it(source_dir):
    """pyenv's python3 before Debian's on PATH loads the native module (same version) but has
    no NumPy: importing ocg, or running an example, names the interpreter ocg was built for
    instead of failing at the first array or with a bare 'No module named numpy'."""
    block_numpy = "import sys; sys.modules['numpy'] = None; "
    script = os.path.join(source_dir, "examples", "change_detector.py")
    for code in ("import ocg",
                 "import runpy; sys.argv = [%r]; runpy.run_path(%r, run_name='__main__')"
                 % (script, script)):
        result = subprocess.run([sys.executable, "-c", block_numpy + code],
                                capture_output=True, text=True)
        assert result.returncode != 0, code
        assert "ocg needs NumPy" in result.stderr, result.stderr
        assert ocg.BUILT_FOR_PYTHON in result.stderr, result.stderr


def test_a_package_folder_without_its_native_module_says_to_build_it(tmp_path):
    """CMake writes build/python/ocg/__init__.py when configuring; the native module is a
    target of its own. Imported before it is built, ocg says so, not that the interpreter
    (the very one it was built for) is the wrong one."""
    package = tmp_path / "ocg"
    package.mkdir()
    shutil.copy(os.path.join(os.path.dirname(ocg.__file__), "__init__.py"), package)
    result = subprocess.run([sys.executable, "-c", "import ocg"], capture_output=True,
                            text=True, env=dict(os.environ, PYTHONPATH=str(tmp_path)))
    assert result.returncode != 0
    assert "native module is not built in %s" % package in result.stderr, result.stderr
    assert "--target ocg_python" in result.stderr, result.stderr
