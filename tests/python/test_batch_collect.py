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


def test_seeds_summary_gives_median_and_worst_acc_and_moves_right_per_preset(tmp_path):
    """seeds.md: per preset and system, over the generated sequences of several seeds, the
    median and the worst Acc (with its seed) and the moves right, summed and as the median of
    each seed's fraction; a seed's figure is the median over its runs; a preset without moves
    has no moves figure."""
    out = str(tmp_path / "out")
    sequences, runs, scores = [], [], {}
    # (preset, seed, acc, moves_right, gt_moves) per gt-poses run
    cases = [("round_2", 1, 0.95, 9, 10), ("round_2", 11, 0.85, 4, 9), ("round_2", 12, 0.90, 8, 8),
             ("desk_static", 1, 1.0, 0, 0), ("desk_static", 11, 0.97, 0, 0)]
    for preset, seed, acc, right, moves in cases:
        name = "%s_s%d" % (preset, seed)
        sequences.append({"name": name, "generated": True, "preset": preset, "seed": seed})
        for variant, shift in (("gt_poses", 0.0), ("slam_poses", -0.1)):
            run = "%s/%s/improved/sequential-1" % (name, variant)
            runs.append(run)
            score = objects_score(right)
            score.update(acc=round(acc + shift, 3), gt_moves=moves)
            scores[run] = {"frames": 10, "frames_tracked": 10, "keyframes": 2, "loops": 0,
                           "tracking_ms": 1.0, "ate": {"rmse": 0.001, "scale": 1.0},
                           "objects": score}
    # A second repeat of one seed: the seed counts once, with its runs' median.
    runs.append("round_2_s12/gt_poses/improved/threaded-1")
    runs.append("round_2_s12/gt_poses/improved/threaded-2")
    for index, acc in ((1, 0.7), (2, 0.8)):
        score = objects_score(6)
        score.update(acc=acc, gt_moves=8)
        scores["round_2_s12/gt_poses/improved/threaded-%d" % index] = {"objects": score}
    write(os.path.join(out, "batch.json"), {"out": out, "runs": runs, "sequences": sequences})
    for run, score in scores.items():
        write(os.path.join(out, "scores", run + ".json"), score)
    done = subprocess.run([sys.executable, COLLECT, os.path.join(out, "batch.json")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    summary = open(os.path.join(out, "seeds.md")).read()
    assert "| preset | variant | mode | execution | seeds | Acc median | Acc worst (seed) |" \
        in summary
    # Fractions 0.9, 0.444, 1.0: median 90 %; moves 21 of 27.
    assert "| round_2 | gt_poses | improved | sequential | 1,11,12 | 0.900 | 0.850 (11) | " \
        "21 of 27 | 90 % |" in summary, summary
    assert "| round_2 | slam_poses | improved | sequential | 1,11,12 | 0.800 | 0.750 (11) |" \
        in summary, summary
    assert "| round_2 | gt_poses | improved | threaded | 12 | 0.750 | 0.750 (12) | 6 of 8 | " \
        "75 % |" in summary, summary
    assert "| desk_static | gt_poses | improved | sequential | 1,11 | 0.985 | 0.970 (11) | - | - |" \
        in summary, summary
    assert summary in done.stdout  # printed too
    rows = open(os.path.join(out, "seeds.csv")).read().splitlines()
    assert rows[0].startswith("preset,variant,mode,execution,seeds,acc_median,acc_worst,")
    assert len(rows) == 1 + 5
    # Sequences of one seed each, without preset (a hand-made batch): no summary.
    plain = make_batch(tmp_path / "plain")
    subprocess.run([sys.executable, COLLECT, os.path.join(plain, "batch.json")], check=True,
                   capture_output=True)
    assert not os.path.exists(os.path.join(plain, "seeds.md"))


def test_seeds_look_images_and_poses_keys_resolve_and_are_checked(source_dir, tools, tmp_path):
    """seeds: makes one sequence per seed (--seeds replaces them), look: and images: reach
    ocg_synth, a variant's poses: groundtruth runs the object layer on the ground truth
    (sequential only), and wrong values stop the batch naming the key."""
    sys.path.insert(0, os.path.join(source_dir, "eval"))
    import batch_config
    config = tmp_path / "b.yaml"

    def load(text, seeds=None):
        config.write_text("tools: %s\nout: out\n%s" % (tools, text))
        return batch_config.load(str(config), tools, None, seeds)

    batch = load("sequences:\n  - {preset: smoke, seeds: [1, 12], look: realistic}\n"
                 "modes: [improved]\nexecutions: [sequential, threaded]\nrepeats: 2\n"
                 "variants:\n  gt: {poses: groundtruth}\n  slam: {Objects.min_confidence: 0.3}\n")
    assert [s["name"] for s in batch["sequences"]] == ["smoke_s1", "smoke_s12"]
    assert batch["sequences"][1]["seed"] == 12 and batch["sequences"][1]["look"] == "realistic"
    assert batch["poses"] == {"gt": "groundtruth", "slam": "slam"}
    assert batch["variants"]["gt"] == {}
    assert [r for r in batch["runs"] if r.startswith("smoke_s1/")] == [
        "smoke_s1/gt/improved/sequential-1", "smoke_s1/slam/improved/sequential-1",
        "smoke_s1/slam/improved/threaded-1", "smoke_s1/slam/improved/threaded-2"]
    batch = load("sequences:\n  - {preset: smoke, seeds: [1, 12]}\n  - {preset: round_2}\n",
                 seeds=batch_config.parse_seeds("21-22,30"))
    assert [s["name"] for s in batch["sequences"]] == [
        "smoke_s21", "smoke_s22", "smoke_s30", "round_2_s21", "round_2_s22", "round_2_s30"]
    gt_only = load("sequences:\n  - {preset: smoke, images: false}\n"
                   "variants: {gt: {poses: groundtruth}}\n")
    assert gt_only["sequences"][0]["images"] is False
    for text, message in [
            ("sequences:\n  - {preset: smoke, seed: 1, seeds: [2]}\n",
             "sequences[0].seeds: give either seed: or seeds:"),
            ("sequences:\n  - {preset: smoke, seeds: [2, 2]}\n",
             "sequences[0].seeds: a seed is listed twice"),
            ("sequences:\n  - {preset: smoke, seeds: [1, 2], name: x}\n",
             "sequences[0].name: a sequence of several seeds is named <preset>_s<seed>"),
            ("sequences:\n  - {preset: smoke, look: shiny}\n",
             "sequences[0].look: expected procedural or realistic, got 'shiny'"),
            ("sequences:\n  - {preset: smoke, images: false}\n",
             "sequences[0].images: false, but a variant runs SLAM on the images"),
            ("sequences:\n  - {preset: smoke}\nvariants: {gt: {poses: gps}}\n",
             "variants.gt.poses: expected slam"),
    ]:
        with pytest.raises(batch_config.ConfigError) as error:
            load(text)
        assert message in str(error.value), str(error.value)
    with pytest.raises(batch_config.ConfigError):
        batch_config.parse_seeds("5-3")
