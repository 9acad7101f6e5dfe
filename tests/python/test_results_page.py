"""tools/results_page.py: the results page is made from a batch's own tables and says how."""
import json
import os
import subprocess
import sys

SOURCE = os.environ.get("OCG_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPT = os.path.join(SOURCE, "tools", "results_page.py")


def make_batch(folder):
    out = folder / "batch_out"
    out.mkdir()
    (out / "batch.json").write_text(json.dumps({
        "out": str(out), "sequences": [{"name": "smoke_s1"}, {"name": "kitti07"}],
        "runs": ["smoke_s1/default/paper/sequential-1", "kitti07/default/slam/sequential-1"]}))
    (out / "table_I.md").write_text("| sequence | Acc |\n|---|---|\n| smoke_s1 | 0.917 |\n")
    (out / "table_II.md").write_text("| sequence | ATE RMSE [mm] |\n|---|---|\n| kitti07 | 338 |\n")
    config = folder / "results.yaml"
    config.write_text("out: batch_out\nsequences:\n  - preset: smoke\n")
    return out, config


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def test_the_page_holds_the_batch_tables_its_configuration_and_the_commands(tmp_path):
    out, config = make_batch(tmp_path)
    page = tmp_path / "results.md"
    done = run(str(out), "--config", str(config), "--out", str(page))
    assert done.returncode == 0, done.stderr
    text = page.read_text()
    assert "| smoke_s1 | 0.917 |" in text
    assert "| kitti07 | 338 |" in text
    assert "preset: smoke" in text
    assert "tools/ocg_batch %s --cores 2" % config in text
    assert "Sequences: smoke_s1, kitti07; 2 runs." in text
    assert not (tmp_path / "results.md.tmp").exists()


def test_a_batch_without_its_tables_is_refused_and_nothing_is_written(tmp_path):
    out, config = make_batch(tmp_path)
    (out / "table_II.md").unlink()
    page = tmp_path / "results.md"
    done = run(str(out), "--config", str(config), "--out", str(page))
    assert done.returncode != 0
    assert "Table II" in done.stderr and "table_II.md" in done.stderr
    assert not page.exists()


def test_the_page_shows_the_object_maps_and_the_runs_snapshots_copied_beside_it(tmp_path):
    out, config = make_batch(tmp_path)
    (out / "objects.md").write_text(
        "| sequence | objects |\n|---|---|\n| fr1_rpy | book 2, keyboard 1 |\n")
    snapshots = out / "runs" / "smoke_s1" / "default" / "paper" / "sequential-1" / "snapshots"
    snapshots.mkdir(parents=True)
    (snapshots / "final_objects.png").write_bytes(b"\x89PNG objects")
    # A second run that drew the same picture (two OCG modes that agree): shown once.
    same = out / "runs" / "smoke_s1" / "default" / "improved" / "sequential-1" / "snapshots"
    same.mkdir(parents=True)
    (same / "final_objects.png").write_bytes(b"\x89PNG objects")
    json_batch = json.loads((out / "batch.json").read_text())
    json_batch["runs"].insert(1, "smoke_s1/default/improved/sequential-1")
    (out / "batch.json").write_text(json.dumps(json_batch))
    docs = tmp_path / "docs"
    docs.mkdir()
    done = run(str(out), "--config", str(config), "--out", str(docs / "results.md"))
    assert done.returncode == 0, done.stderr
    text = (docs / "results.md").read_text()
    assert "## What each object map holds" in text and "| fr1_rpy | book 2, keyboard 1 |" in text
    copied = docs / "images" / "results" / "smoke_s1_default_paper_sequential-1_final_objects.png"
    assert copied.read_bytes() == b"\x89PNG objects"
    assert "](images/results/smoke_s1_default_paper_sequential-1_final_objects.png)" in text
    assert sorted(os.listdir(docs / "images" / "results")) == [copied.name]
    assert "as smoke_s1/default/paper/sequential-1's." in text
    # The kitti run drew none: no picture, no heading for it.
    assert "### kitti07" not in text
