"""ocg.read_tum_trajectory, ocg.ate and ocg.object_metrics against ocg_eval."""
import json
import os

import numpy as np
import pytest

import ocg
from conftest import run_tool


def write_tum(path, rows):
    with open(path, "w") as handle:
        for row in rows:
            handle.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % tuple(row))


def perturbed_estimate(gt, seed):
    """gt in another frame and scale (a monocular run), with noise and a time offset."""
    rng = np.random.default_rng(seed)
    angle = 0.7
    rotation = np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0],
                         [0, 0, 1]])
    est = gt.copy()
    est[:, 0] += 0.004
    est[:, 1:4] = 0.37 * (gt[:, 1:4] @ rotation.T) + [1.0, -2.0, 0.5]
    est[:, 1:4] += rng.normal(0.0, 0.01, size=(len(gt), 3))
    return est


def helix(count=200):
    t = np.linspace(0.0, 20.0, count)
    rows = np.zeros((count, 8))
    rows[:, 0] = 1000.0 + t
    rows[:, 1:4] = np.stack([np.cos(t), np.sin(t), 0.05 * t], axis=1)
    rows[:, 7] = 1.0
    return rows


def check_ate_matches_ocg_eval(tools, gt_path, est_path):
    for align in ("sim3", "se3", "none"):
        expected = json.loads(run_tool(tools, "ocg_eval", "ate", "--gt", gt_path, "--est",
                                       est_path, "--align", align, "--json"))
        got = ocg.ate(gt_path, est_path, align=align)
        assert got.count == expected["pairs"]
        assert got.scale == pytest.approx(expected["scale"], rel=1e-12)
        for field in ("rmse", "mean", "median", "std", "min", "max"):
            assert getattr(got, field) == pytest.approx(expected[field], rel=1e-12), field
        # Arrays give the same result as the files they came from.
        from_arrays = ocg.ate(ocg.read_tum_trajectory(gt_path),
                              ocg.read_tum_trajectory(est_path), align=align)
        assert from_arrays.rmse == pytest.approx(got.rmse, rel=1e-9)
    return got


def test_ate_matches_ocg_eval_on_a_helix(tools, tmp_path):
    gt = helix()
    write_tum(tmp_path / "gt.txt", gt)
    write_tum(tmp_path / "est.txt", perturbed_estimate(gt, seed=3))
    result = ocg.ate(str(tmp_path / "gt.txt"), str(tmp_path / "est.txt"))
    # The noise is 1 cm per axis in the estimate's scale 0.37: about 2.7 cm per axis back
    # in the ground truth's scale, 4.7 cm in 3D.
    assert 0.03 < result.rmse < 0.07
    assert result.scale == pytest.approx(1 / 0.37, rel=0.02)
    check_ate_matches_ocg_eval(tools, str(tmp_path / "gt.txt"), str(tmp_path / "est.txt"))
    aligned = result.alignment @ np.array([1.0 * 0.37 + 1.0, -2.0, 0.5, 1.0])
    assert aligned[3] == pytest.approx(1.0)


def test_ate_matches_ocg_eval_on_kitti_ground_truth(tools, shared_data, tmp_path):
    gt_path = os.path.join(shared_data, "kitti_07_first160", "groundtruth.txt")
    gt = ocg.read_tum_trajectory(gt_path)
    assert gt.shape == (160, 8)
    write_tum(tmp_path / "est.txt", perturbed_estimate(gt, seed=5))
    check_ate_matches_ocg_eval(tools, gt_path, str(tmp_path / "est.txt"))


def test_read_tum_trajectory_errors_name_the_file(tmp_path):
    with pytest.raises(ocg.FileError, match="nope.txt"):
        ocg.read_tum_trajectory(tmp_path / "nope.txt")
    bad = tmp_path / "bad.txt"
    bad.write_text("1.0 0 0 0 0 0 0 1\n2.0 0 0 zero 0 0 0 1\n")
    with pytest.raises(ocg.ParseError, match="bad.txt:2"):
        ocg.read_tum_trajectory(bad)
    with pytest.raises(ValueError, match=r"\(N, 8\)"):
        ocg.ate(np.zeros((5, 7)), helix())
    with pytest.raises(ValueError, match="align"):
        ocg.ate(helix(), helix(), align="affine")


def test_read_tum_trajectory_reads_reference_files_as_the_fields_tools_do(tmp_path):
    """A time listed twice (TUM's fr2_desk ground truth) keeps its first pose; lines out of
    order are sorted; commas separate fields as in associate.py."""
    path = tmp_path / "groundtruth.txt"
    path.write_text("# timestamp tx ty tz qx qy qz qw\n"
                    "1311868229.5760,1,0,0,0,0,0,1\n"
                    "1311868229.5760 2 0 0 0 0 0 1\n"
                    "1311868229.5660 3 0 0 0 0 0 1\n")
    rows = ocg.read_tum_trajectory(path)
    np.testing.assert_array_equal(rows[:, 0], [1311868229.5660, 1311868229.5760])
    np.testing.assert_array_equal(rows[:, 1], [3, 1])


def write_json(path, value):
    with open(path, "w") as handle:
        json.dump(value, handle)


def test_object_metrics_matches_ocg_eval(tools, tmp_path):
    # Ground truth: a cup that stays, a book moved from x = 1 to x = 2.
    def placement(centre, present=True):
        return {"centre": centre, "present": present, "time": 0.0, "yaw": 0.0}
    write_json(tmp_path / "objects_gt.json", {"objects": [
        {"id": 1, "class_id": 41, "size": [0.1, 0.1, 0.1], "history": [placement([0, 0, 0])]},
        {"id": 2, "class_id": 73, "size": [0.2, 0.2, 0.05],
         "history": [placement([1, 0, 0]), placement([2, 0, 0])]},
        # A remote the sequence never shows: no ground truth unless asked for.
        {"id": 3, "class_id": 65, "size": [0.05, 0.18, 0.02],
         "history": [dict(placement([4, 0, 0]), frames_in_view=0)]}]})
    # A monocular run: its frame is the ground truth's scaled by 2. It found the cup, kept
    # the book at its old place, and saw nothing at the new one.
    run = tmp_path / "run"
    run.mkdir()
    write_json(run / "objects.json", {"format": "ocg-objects", "objects": [
        {"id": 10, "class_id": 41, "cuboid": {"centre": [0.02, 0.0, 0.0]}},
        {"id": 11, "class_id": 73, "cuboid": {"centre": [2.0, 0.0, 0.0]}}]})
    write_json(run / "changes.json", {"changes": []})
    gt = helix(50)
    write_tum(tmp_path / "groundtruth.txt", gt)
    scaled = gt.copy()
    scaled[:, 1:4] *= 2.0
    write_tum(run / "KeyFrameTrajectory.txt", scaled)

    expected = json.loads(run_tool(tools, "ocg_eval", "objects", "--gt",
                                   str(tmp_path / "objects_gt.json"), "--run", str(run),
                                   "--groundtruth", str(tmp_path / "groundtruth.txt"), "--json"))
    got = ocg.object_metrics(tmp_path / "objects_gt.json", run, tmp_path / "groundtruth.txt")
    assert got == expected
    assert got["corr_s"] == 1 and got["unident_s"] == 1 and got["unident_m"] == 1
    assert got["alignment"]["scale"] == pytest.approx(0.5)
    assert got["gt_never_in_view"] == 1 and got["never_in_view_ids"] == [3]
    every = ocg.object_metrics(tmp_path / "objects_gt.json", run, tmp_path / "groundtruth.txt",
                               include_never_in_view=True)
    assert every == json.loads(run_tool(tools, "ocg_eval", "objects", "--gt",
                                        str(tmp_path / "objects_gt.json"), "--run", str(run),
                                        "--groundtruth", str(tmp_path / "groundtruth.txt"),
                                        "--include-never-in-view", "--json"))
    assert every["unident_s"] == 2 and every["gt_never_in_view"] == 0
    # Without the trajectory the run is taken in the ground truth's frame: the cup at 2 cm
    # still matches, the book at x = 2 now sits on the book's new place.
    plain = ocg.object_metrics(tmp_path / "objects_gt.json", run)
    assert plain["alignment"] is None and plain["corr_s"] == 2
    with pytest.raises(ocg.FileError, match="objects.json"):
        ocg.object_metrics(tmp_path / "objects_gt.json", tmp_path)
