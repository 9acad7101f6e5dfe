"""ocg.ChangeDetector against the C++ replay tool, and its errors."""
import json
import os

import numpy as np
import pytest

import ocg
from conftest import run_tool


def replay_through_bindings(path, options):
    detector = ocg.ChangeDetector(options)
    lines = []
    for text in open(path):
        if not text.strip():
            continue
        record = json.loads(text)
        states = detector.process(
            record["keyframe"],
            np.array(record["T_cw"], dtype=float).reshape(4, 4),
            ocg.PinholeCamera(**record["camera"]),
            record["observed"],
            {int(k): v for k, v in record.get("centroids", {}).items()},
            timestamp=record["timestamp"],
            sizes={int(k): v for k, v in record.get("sizes", {}).items()},
            classes={int(k): v for k, v in record.get("classes", {}).items()})
        lines.append({"keyframe": states.keyframe,
                      "objects": [{"id": s.id, "state": s.state, "doubt": s.doubt,
                                   "active_edge_rate": s.active_edge_rate} for s in states.objects],
                      "removed": [event.object_id for event in states.removed]})
    return lines


@pytest.mark.parametrize("mode", ["paper", "improved"])
def test_replay_example_matches_ocg_replay(tools, source_dir, tmp_path, mode):
    example = os.path.join(source_dir, "tests", "data", "ocg_example.jsonl")
    run_tool(tools, "ocg_replay", "--input", example, "--out", str(tmp_path), "--mode", mode,
             "--log-level", "warn")
    expected = [json.loads(line) for line in open(tmp_path / "states.jsonl")]
    got = replay_through_bindings(example, ocg.OcgOptions(mode=mode))
    assert len(got) == len(expected) == 9
    # Exact: the same C++ code computes both, and JSON keeps every bit of a double.
    assert got == expected
    # The example's story (docs/ocg.md): the moved cup, object 1, is removed at keyframe 7
    # after two keyframes in state 4 with doubt 30 and 60.
    assert [line["removed"] for line in got][7] == [1]
    cup = [next((o for o in line["objects"] if o["id"] == 1), None) for line in got]
    assert [(c["state"], c["doubt"]) for c in cup[5:7]] == [(4, 30.0), (4, 60.0)]


def test_a_removed_object_seen_again_keeps_its_centroid(tools, tmp_path):
    """SPEC 3.1's nine keyframes: object 1's centroid (0, 0, 2) is sent once, at keyframe 0;
    removed at keyframe 5 and seen again at 6, it is suspicious again at 8 (doubt 30), as
    ocg_replay says."""
    seen = [[1, 2], [2], [3], [2], [2], [3], [1, 2], [3], [2]]
    camera = {"fx": 500, "fy": 500, "cx": 320, "cy": 240, "width": 640, "height": 480}
    stream = tmp_path / "reentry.jsonl"
    with open(stream, "w") as out:
        for k, observed in enumerate(seen):
            out.write(json.dumps({"keyframe": k, "timestamp": float(k),
                                  "T_cw": np.eye(4).ravel().tolist(), "camera": camera,
                                  "observed": observed,
                                  "centroids": {"1": [0, 0, 2]} if k == 0 else {}}) + "\n")
    got = replay_through_bindings(stream, ocg.OcgOptions(mode="paper"))
    run_tool(tools, "ocg_replay", "--input", str(stream), "--out", str(tmp_path / "out"),
             "--mode", "paper", "--log-level", "warn")
    assert got == [json.loads(line) for line in open(tmp_path / "out" / "states.jsonl")]
    assert got[5]["removed"] == [1]
    object_1 = [next(((o["state"], o["doubt"]) for o in line["objects"] if o["id"] == 1), None)
                for line in got]
    assert object_1 == [(1, 0), (2, 0), (3, 0), (4, 30), (4, 60), None, (1, 0), (3, 0), (4, 30)]


def test_restored_object_comes_back_with_its_history(source_dir):
    # The example's cup (object 1) is removed at keyframe 7; found again at its place, the
    # object map says so ("restored"): with restore (part of improved) it is back in state 1
    # with its observations, in paper mode it is a new node.
    example = os.path.join(source_dir, "tests", "data", "ocg_example.jsonl")
    first = json.loads(open(example).readline())
    observations = {}
    for mode in ("improved", "paper"):
        detector = ocg.ChangeDetector(ocg.OcgOptions(mode=mode))
        for text in open(example):
            record = json.loads(text)
            detector.process(record["keyframe"], np.array(record["T_cw"], dtype=float).reshape(4, 4),
                             ocg.PinholeCamera(**record["camera"]), record["observed"],
                             {int(k): v for k, v in record.get("centroids", {}).items()})
        assert detector.status(1) is None
        states = detector.process(9, np.array(first["T_cw"], dtype=float).reshape(4, 4),
                                  ocg.PinholeCamera(**first["camera"]), first["observed"],
                                  restored=[1])
        cup = next(o for o in states.objects if o.id == 1)
        assert (cup.state, cup.doubt) == (1, 0.0)
        observations[mode] = detector.status(1).observations
    assert observations["paper"] == 1
    assert observations["improved"] > 1


def test_removal_event_names_the_object():
    detector = ocg.ChangeDetector()
    camera = ocg.PinholeCamera(500.0, 500.0, 320.0, 240.0, 640, 480)
    pose = np.eye(4)
    centroids = {1: [0.0, 0.0, 2.0], 2: [0.2, 0.0, 2.0], 3: [-0.2, 0.0, 2.0]}
    for keyframe in range(3):
        detector.process(keyframe, pose, camera, [1, 2, 3], centroids if keyframe == 0 else {},
                         classes={1: 41})
    removed = []
    # The camera looks elsewhere (object 1 is taken away meanwhile) ...
    for keyframe in (3, 4):
        removed += detector.process(keyframe, pose, camera, []).removed
    # ... comes back: its neighbours are detected, object 1 is not: suspicious, doubt 30
    # then 60 ...
    for keyframe in (5, 6):
        removed += detector.process(keyframe, pose, camera, [2, 3]).removed
    assert detector.status(1).state == 4 and detector.status(1).doubt == 60.0
    # ... and looks away again: object 1 leaves the observable region with its doubt
    # above tau_doubt (50) and is removed.
    removed += detector.process(7, pose, camera, []).removed
    assert [event.object_id for event in removed] == [1]
    assert removed[0].class_id == 41
    assert np.allclose(removed[0].centroid, [0.0, 0.0, 2.0])
    assert detector.status(1) is None and len(detector) == 2


def test_options_errors_keep_the_message():
    with pytest.raises(ValueError, match="OCG.mode: unknown mode 'nonsense'"):
        ocg.OcgOptions(mode="nonsense")
    with pytest.raises(ValueError, match="unknown option 'tau'"):
        ocg.OcgOptions(tau=1.0)
    assert ocg.OcgOptions(tau_doubt=40.0).tau_doubt == 40.0


def test_options_from_settings_file(tmp_path):
    good = tmp_path / "good.yaml"
    good.write_text("OCG:\n  mode: improved\n  tau_doubt: 70\n")
    options = ocg.OcgOptions.from_settings(str(good))
    assert (options.mode, options.tau_doubt) == ("improved", 70.0)
    bad = tmp_path / "bad.yaml"
    bad.write_text("OCG:\n  tau_doubt: many\n")
    with pytest.raises(ocg.SettingsError, match=r"bad.yaml:2.*OCG.tau_doubt"):
        ocg.OcgOptions.from_settings(str(bad))


def test_process_rejects_what_is_not_a_pose():
    detector = ocg.ChangeDetector()
    camera = ocg.PinholeCamera(500.0, 500.0, 320.0, 240.0, 640, 480)
    scaled = np.eye(4)
    scaled[:3, :3] *= 2.0
    with pytest.raises(ValueError, match="T_cw rotation block is not a rotation"):
        detector.process(0, scaled, camera, [1])
    with pytest.raises(ValueError, match=r"centroids\[1\] is not finite"):
        detector.process(0, np.eye(4), camera, [1], {1: [np.nan, 0.0, 1.0]})
    with pytest.raises(ValueError, match="fx"):
        ocg.PinholeCamera(-1.0, 500.0, 320.0, 240.0, 640, 480)
    assert len(detector) == 0  # nothing half-applied


def test_example_script_tells_the_cup_story(source_dir):
    import subprocess
    import sys
    script = os.path.join(source_dir, "examples", "change_detector.py")
    result = subprocess.run([sys.executable, script], capture_output=True, text=True, check=True)
    assert "removed object 1 (class 41, doubt 60)" in result.stdout
    assert result.stdout.strip().endswith("6 objects left in the map")


# A value unlike the default for each type a field of the observation has (by the type
# ocg.observation_fields() gives); n makes fields of one type differ. A field of a type
# not here fails the test until it is added.
def sample_value(field, n):
    pose = [[0.0, -1.0, 0.0, 0.5], [1.0, 0.0, 0.0, -0.25], [0.0, 0.0, 1.0, 2.0 + n],
            [0.0, 0.0, 0.0, 1.0]]
    camera = {"fx": 510.5, "fy": 511.25, "cx": 300.5, "cy": 250.75, "width": 800,
              "height": 600, "k1": 0.125, "k2": -0.0625, "k3": 0.03125, "p1": 0.001,
              "p2": -0.002}
    samples = {
        "integer": 100 + n,
        "number": 0.375 + n,
        "4x4 matrix (replay: 16 numbers, row-major)": pose,
        "camera": camera,
        "list of object ids": [n, 2 * n + 1],
        "{object id: [x, y, z]}": {3: [0.5 * n, 0.25, 1.125], 7: [0.0, 0.5 * n, 2.0]},
        "{object id: integer}": {3: 40 + n, 7: 60},
    }
    assert field["type"] in samples, "no sample for the type of " + field["name"]
    return samples[field["type"]]


def every_field_set():
    return {field["name"]: sample_value(field, n)
            for n, field in enumerate(ocg.observation_fields(), start=1)}


def assert_same_observation(got, expected):
    """Equal field by field; T_cw to rounding (it goes through a quaternion)."""
    assert set(got) == set(expected)
    assert np.allclose(got["T_cw"], expected["T_cw"], rtol=0, atol=1e-12)
    assert {k: v for k, v in got.items() if k != "T_cw"} == \
        {k: v for k, v in expected.items() if k != "T_cw"}


def test_every_observation_field_round_trips():
    """process() and the replay line take and give back every field of the OCG's one field
    list (present_by_points too, which process() once refused)."""
    fields = ocg.observation_fields()
    names = [field["name"] for field in fields]
    assert {"keyframe", "T_cw", "camera", "observed", "centroids", "sizes", "classes",
            "forgotten", "restored", "present_by_points"} <= set(names)
    given = every_field_set()
    detector = ocg.ChangeDetector(ocg.OcgOptions(mode="improved"))
    states = detector.process(given)
    assert states.keyframe == given["keyframe"]
    assert_same_observation(states.observation, given)
    line = ocg.observation_to_json(given)
    assert set(json.loads(line)) == set(names)
    assert_same_observation(ocg.observation_from_json(line), given)
    # Keys from json.loads (object ids as str) are accepted as they are.
    assert ocg.observation_to_json(json.loads(line)) == line
    with_objects = {o.id for o in states.objects}
    assert set(given["observed"]) <= with_objects


def test_observation_dicts_feed_the_replay_example(tools, source_dir, tmp_path):
    example = os.path.join(source_dir, "tests", "data", "ocg_example.jsonl")
    run_tool(tools, "ocg_replay", "--input", example, "--out", str(tmp_path), "--mode",
             "improved", "--log-level", "warn")
    expected = [json.loads(line) for line in open(tmp_path / "states.jsonl")]
    detector = ocg.ChangeDetector(ocg.OcgOptions(mode="improved"))
    got = []
    for text in open(example):
        states = detector.process(json.loads(text))
        got.append({"keyframe": states.keyframe,
                    "objects": [{"id": s.id, "state": s.state, "doubt": s.doubt,
                                 "active_edge_rate": s.active_edge_rate}
                                for s in states.objects],
                    "removed": [event.object_id for event in states.removed]})
    assert got == expected


def test_present_by_points_keeps_an_undetected_object():
    """The 'points' evidence through process(): object 1, suspicious (doubt 30) while its
    neighbours are detected, is present by its points: state 1, doubt cleared; ignored in
    paper mode."""
    camera = ocg.PinholeCamera(500.0, 500.0, 320.0, 240.0, 640, 480)
    centroids = {1: [0.0, 0.0, 2.0], 2: [0.2, 0.0, 2.0], 3: [-0.2, 0.0, 2.0]}
    results = {}
    for mode in ("improved", "paper"):
        detector = ocg.ChangeDetector(ocg.OcgOptions(mode=mode))
        for keyframe in range(3):
            detector.process(keyframe, np.eye(4), camera, [1, 2, 3],
                             centroids if keyframe == 0 else {},
                             sizes={i: [0.1, 0.1, 0.1] for i in centroids})
        for keyframe in (3, 4):
            detector.process(keyframe, np.eye(4), camera, [])
        detector.process(5, np.eye(4), camera, [2, 3])
        before = detector.status(1)
        states = detector.process(6, np.eye(4), camera, [2, 3], present_by_points=[1])
        after = next(o for o in states.objects if o.id == 1)
        results[mode] = ((before.state, before.doubt), (after.state, after.doubt))
    assert results["paper"][0][0] == 4 and results["paper"][0][1] > 0
    assert results["paper"][1][0] == 4 and results["paper"][1][1] > results["paper"][0][1]
    assert results["improved"][1] == (1, 0.0)


def test_observation_errors_name_the_field():
    detector = ocg.ChangeDetector()
    good = every_field_set()
    cases = [
        ({"present_by_point": [1]}, r"unknown field 'present_by_point' \(known: keyframe"),
        ({"observed": [1, "two"]}, r"observed\[1\] must be an integer"),
        ({"sizes": {3: [0.1, -0.1, 0.1]}}, r"sizes\[3\] must be non-negative"),
        ({"centroids": {"x": [0, 0, 1]}}, r"centroids key must be an object id, got 'x'"),
        ({"T_cw": [[1, 0, 0, 0]] * 4}, r"T_cw last row must be \[0, 0, 0, 1\]"),
        ({"T_cw": np.eye(3)}, r"T_cw must be a \(4, 4\) matrix or 16 numbers"),
        ({"camera": {"fx": 500.0}}, r"camera: missing field 'fy'"),
        ({"camera": dict(good["camera"], model="pinhole")}, r"camera: unknown field 'model'"),
        ({"timestamp": "noon"}, r"timestamp must be a number"),
        ({"classes": [41]}, r"classes must be a dict \{object id: class\}"),
    ]
    for change, message in cases:
        with pytest.raises(ValueError, match=message):
            detector.process(dict(good, **change))
    missing = dict(good)
    del missing["keyframe"]
    with pytest.raises(ValueError, match="missing field 'keyframe'"):
        detector.process(missing)
    with pytest.raises(ValueError, match="unknown field 'colour'"):
        detector.process(1, np.eye(4), ocg.PinholeCamera(500.0, 500.0, 320.0, 240.0, 640, 480),
                         [1], colour={1: 3})
    with pytest.raises(TypeError, match="multiple values for 'keyframe'"):
        detector.process(1, keyframe=2)
    assert len(detector) == 0  # nothing half-applied


def test_ocg_replay_lists_the_same_fields(tools):
    listed = run_tool(tools, "ocg_replay", "--fields").splitlines()
    assert [line.split(":")[0] for line in listed] == \
        [field["name"] for field in ocg.observation_fields()]
    assert "present_by_points: list of object ids (optional);" in "\n".join(listed)
