"""eval/collect.py on a constructed batch (no runs): Table I reports the moves the change
log got right, Table II the loops, timing.md the tracking time, objects.md what each object map
holds (also on a sequence without object ground truth); and the batch configuration's
`detect:` and `snapshots:` keys are checked before any job."""
import json
import os
import subprocess
import sys

import pytest

SOURCE = os.environ.get("OCG_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
COLLECT = os.path.join(SOURCE, "eval", "collect.py")


def write(path, value):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as handle:
        json.dump(value, handle)


def objects_score(moves_right):
    return {"corr_s": 7, "unident_s": 0, "redun_s": 1, "redun_duplicates": 1,
            "redun_spurious": 0, "corr_m": 1, "delet_s": 0, "unident_m": 0, "acc": 0.8,
            "prec": 0.9, "recall": 1.0, "gt_static": 7, "gt_outdated": 1, "gt_moves": 1,
            "moves_right": moves_right}


def make_batch(folder):
    out = str(folder / "out")
    runs = ["smoke/default/paper/sequential-1", "smoke/default/improved/sequential-1",
            "desk/default/improved/sequential-1", "kitti/default/slam/sequential-1"]
    batch = {"out": out, "runs": runs, "sequences": [
        {"name": "smoke", "generated": True}, {"name": "desk", "generated": False,
                                                "detect": ["--score", "0.4"]},
        {"name": "kitti", "generated": False}]}
    write(os.path.join(out, "batch.json"), batch)
    ate = {"rmse": 0.0021, "scale": 1.0}
    scores = {runs[0]: {"frames": 550, "frames_tracked": 549, "keyframes": 98, "loops": 1,
                        "tracking_ms": 14.23, "ate": ate, "objects": objects_score(0)},
              runs[1]: {"frames": 550, "frames_tracked": 549, "keyframes": 98, "loops": 1,
                        "tracking_ms": 14.31, "ate": ate, "objects": objects_score(1)},
              runs[2]: {"frames": 330, "frames_tracked": 302, "keyframes": 48, "loops": 0,
                        "tracking_ms": 12.0, "ate": ate},
              runs[3]: {"frames": 160, "frames_tracked": 160, "keyframes": 60, "loops": 0,
                        "tracking_ms": 40.0, "ate": {"rmse": 0.338, "scale": 1.0}}}
    for run, score in scores.items():
        write(os.path.join(out, "scores", run + ".json"), score)
    # The desk run's maps: a removal undone by a restore is no removal; a move is one.
    desk = os.path.join(out, "runs", runs[2])
    write(os.path.join(desk, "objects.json"), {"objects": [
        {"id": 1, "class": "keyboard"}, {"id": 2, "class": "book"}, {"id": 3, "class": "book"},
        {"id": 4, "class": "tv"}]})
    write(os.path.join(desk, "changes.json"), {"changes": [
        {"type": "removed", "object_id": 2}, {"type": "restored", "object_id": 2},
        {"type": "merged", "object_id": 5}, {"type": "moved", "object_id": 6}]})
    smoke = os.path.join(out, "runs", runs[1])
    write(os.path.join(smoke, "objects.json"), {"objects": [{"id": 1, "class": "cup"}]})
    write(os.path.join(smoke, "changes.json"), {"changes": []})
    return out


def test_tables_report_moves_loops_and_what_each_object_map_holds(tmp_path):
    out = make_batch(tmp_path)
    done = subprocess.run([sys.executable, COLLECT, os.path.join(out, "batch.json")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    table_one = open(os.path.join(out, "table_I.md")).read()
    assert "| Moves right |" in table_one
    assert "| smoke | default | paper | sequential | 1 | 7 |" in table_one
    rows = {[cell.strip() for cell in line.strip("|").split("|")][2]: line
            for line in table_one.splitlines() if "| smoke |" in line}
    assert rows["paper"].endswith("| 0 of 1 |") and rows["improved"].endswith("| 1 of 1 |")
    assert rows["GT"].endswith("| 1 |")
    table_two = open(os.path.join(out, "table_II.md")).read()
    assert "| loops closed |" in table_two
    assert "| kitti | default | slam | sequential | 1 | 0 | 160 | 160 | 60 | 0 | 338 | 1.000 |" \
        in table_two
    # Wall-clock time apart: the tables stay the same on every machine and re-run.
    assert "ms/frame" not in table_two
    timing = open(os.path.join(out, "timing.md")).read()
    assert "| smoke | default | improved | sequential | 1 | 14.3 |" in timing
    objects = open(os.path.join(out, "objects.md")).read()
    assert "| desk | default | improved | sequential | 1 | 4 | book 2, keyboard 1, tv 1 | 1 | 1 |" \
        in objects
    assert "| smoke | default | improved | sequential | 1 | 1 | cup 1 | 0 | 0 |" in objects
    # No object map: no row (the paper run wrote none here; kitti ran without detections).
    assert "| paper |" not in objects and "| kitti |" not in objects


def test_a_table_i_without_rows_says_why(tmp_path):
    """Real sequences without objects_gt: Table I has no row, and says so under its header."""
    out = make_batch(tmp_path)
    for run in ("smoke/default/paper/sequential-1", "smoke/default/improved/sequential-1"):
        path = os.path.join(out, "scores", run + ".json")
        score = json.load(open(path))
        del score["objects"]
        write(path, score)
    done = subprocess.run([sys.executable, COLLECT, os.path.join(out, "batch.json")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    table_one = open(os.path.join(out, "table_I.md")).read()
    assert "| smoke |" not in table_one
    assert "No row: Table I scores object maps against an object ground truth" in table_one
    with_rows = make_batch(tmp_path / "with")
    subprocess.run([sys.executable, COLLECT, os.path.join(with_rows, "batch.json")], check=True)
    assert "No row" not in open(os.path.join(with_rows, "table_I.md")).read()


def tum_folder(folder):
    sequence = folder / "seq"
    (sequence / "rgb").mkdir(parents=True)
    (sequence / "rgb" / "0.png").write_bytes(b"")
    (sequence / "rgb.txt").write_text("0.0 rgb/0.png\n")
    (folder / "s.yaml").write_text("Camera.fx: 500\n")
    return sequence


def refusal(source_dir, tools, folder, sequence_entry):
    """ocg_batch on a configuration of one sequence (its YAML flow mapping), expected to stop
    before any job: the error text; asserts exit status 1 and no output folder."""
    config = folder / "batch.yaml"
    config.write_text("tools: %s\nout: out\nsequences:\n  - %s\n" % (tools, sequence_entry))
    done = subprocess.run([os.path.join(source_dir, "tools", "ocg_batch"), str(config)],
                          capture_output=True, text=True)
    assert done.returncode == 1
    assert not (folder / "out").exists()
    return done.stderr


@pytest.mark.parametrize("entry, message", [
    ("detect: {score: 2}", "sequences[0].detect.score: expected a confidence in (0, 1), got 2"),
    ("detect: {scor: 0.3}", "sequences[0].detect.scor: unknown key (known: model, score, tile)"),
    ("detect: {tile: on}", "sequences[0].detect.tile: expected auto or off"),
    ("detect: true, detections: seq", "sequences[0].detect: give either detect:"),
    ("snapshots: final", "sequences[0].snapshots: expected true"),
])
def test_detect_and_snapshots_keys_are_checked_before_any_job(source_dir, tools, tmp_path, entry,
                                                              message):
    tum_folder(tmp_path)
    stderr = refusal(source_dir, tools, tmp_path, "{path: seq, settings: s.yaml, %s}" % entry)
    assert message in stderr, stderr


def test_a_detections_folder_inside_the_sequence_given_as_groundtruth_is_named(source_dir, tools,
                                                                              tmp_path):
    """groundtruth: is relative to the sequence folder, detections: to the configuration: a
    user writing `detections: detections` for SEQ/detections is told the path to give."""
    sequence = tum_folder(tmp_path)
    (sequence / "detections").mkdir()
    stderr = refusal(source_dir, tools, tmp_path,
                     "{path: seq, settings: s.yaml, detections: detections}")
    assert "sequences[0].detections: no such folder: %s" % (tmp_path / "detections") \
        in stderr, stderr
    assert "the sequence's own is %s" % (sequence / "detections") in stderr, stderr


def test_a_sequences_own_settings_keys_are_read_strictly_before_any_job(source_dir, tools,
                                                                        tmp_path):
    stderr = refusal(source_dir, tools, tmp_path,
                     "{preset: smoke, set: {Objects.min_confidenc: 0.3}}")
    assert "sequences[0].set:" in stderr, stderr
    assert "did you mean 'Objects.min_confidence'?" in stderr, stderr
