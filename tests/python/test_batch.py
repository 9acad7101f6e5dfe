"""tools/ocg_batch: the configuration check, the Slurm profile's dry run, and a local
two-sequence batch (generated smoke sequences, 20 frames) that resumes after losing a run."""
import csv
import os
import subprocess

import pytest


def ocg_batch(source_dir, *arguments, cwd=None):
    return subprocess.run([os.path.join(source_dir, "tools", "ocg_batch"), *arguments],
                          capture_output=True, text=True, cwd=cwd)


def write_config(folder, tools, text):
    path = os.path.join(folder, "batch.yaml")
    with open(path, "w") as handle:
        handle.write("tools: %s\n" % tools + text)
    return path


TWO_SMOKES = """out: out
sequences:
  - {preset: smoke, seed: 1, frames: 20}
  - {preset: smoke, seed: 2, frames: 20}
modes: [paper]
executions: [sequential, threaded]
repeats: 2
"""


@pytest.mark.parametrize("text, message", [
    ("out: o\nsequences:\n  - {preset: smoke}\n  - {preset: smok}\n",
     "sequences[1].preset: unknown preset 'smok' (known: smoke"),
    ("out: o\nsequences: [{preset: smoke}]\nrepeat: 3\n", ": repeat: unknown key"),
    ("out: o\nsequences: [{preset: smoke}]\nrepeats: 0\n", ": repeats: expected a whole number >= 1"),
    ("out: o\nsequences: [{preset: smoke}]\nmodes: [paper, clever]\n", ": modes[1]: unknown OCG mode"),
    ("sequences: [{preset: smoke}]\n", ": out: required"),
    ("out: o\nsequences: [{path: nowhere, settings: s.yaml}]\n", "sequences[0].path: no such folder"),
    ("out: o\nsequences: [{preset: smoke}]\nvariants: {v: {System.sequential: true}}\n",
     "variants.v.System.sequential: set by executions"),
])
def test_config_errors_name_the_key_and_nothing_runs(source_dir, tools, tmp_path, text, message):
    config = write_config(tmp_path, tools, text)
    result = ocg_batch(source_dir, config, "--cores", "1")
    assert result.returncode != 0
    assert "ocg_batch: error: %s" % config in result.stderr
    assert message in result.stderr, result.stderr
    assert sorted(os.listdir(tmp_path)) == ["batch.yaml"]  # no job started, nothing written


def test_help(source_dir):
    result = ocg_batch(source_dir, "--help")
    assert result.returncode == 0 and "--slurm" in result.stdout and "--cores" in result.stdout


def test_slurm_profile_dry_run(source_dir, tools, tmp_path):
    config = write_config(tmp_path, tools, TWO_SMOKES)
    result = ocg_batch(source_dir, config, "--slurm", "--dry-run")
    assert result.returncode == 0, result.stdout + result.stderr
    output = result.stdout + result.stderr
    # Every job of the batch, with the profile's Slurm resources.
    assert output.count("rule run:") == 6 and output.count("rule sequence:") == 2
    assert output.count("slurm_partition=main") == 20
    assert not os.path.exists(tmp_path / "out" / "runs")  # a dry run runs nothing


def read_csv(path):
    with open(path) as handle:
        return list(csv.DictReader(handle))


def test_local_batch_tables_plots_and_resume(source_dir, tools, tmp_path):
    from matplotlib import image
    config = write_config(tmp_path, tools, TWO_SMOKES)
    result = ocg_batch(source_dir, config, "--cores", "2")
    assert result.returncode == 0, result.stderr[-3000:]
    out = tmp_path / "out"

    table_two = read_csv(out / "table_II.csv")
    assert [(r["sequence"], r["execution"], r["runs"], r["failed"]) for r in table_two] == [
        ("smoke_s1", "sequential", "1", "0"), ("smoke_s1", "threaded", "2", "0"),
        ("smoke_s2", "sequential", "1", "0"), ("smoke_s2", "threaded", "2", "0")]
    for row in table_two:
        low, median, high = (float(row["ate_%s_mm" % k]) for k in ("min", "median", "max"))
        assert 0 < low <= median <= high < 10.0  # smoke is tracked to about a millimetre
    table_one = read_csv(out / "table_I.csv")
    assert len(table_one) == 4
    for row in table_one:
        assert int(row["gt_static"]) > 0
        assert float(row["corr_s_min"]) <= float(row["corr_s_median"]) <= float(row["corr_s_max"])
    markdown = (out / "table_I.md").read_text()
    assert "| Corr.S | Unident.S |" in markdown and "| smoke_s2 | | GT |" in markdown
    assert "| ATE RMSE [mm] |" in (out / "table_II.md").read_text()

    plots = [out / "plots" / "ate.png"] + sorted((out / "plots" / "trajectories").rglob("*.png"))
    assert len(plots) == 7
    for plot in plots:
        pixels = image.imread(str(plot))[:, :, :3]
        assert (abs(pixels - 1.0).sum(axis=2) > 0.1).mean() > 0.02, plot  # not blank

    # An interrupted batch: one run and its score lost (as when the batch stopped during
    # that run). The rerun redoes that run only, and the sequential run comes out
    # byte-identical.
    lost = out / "runs" / "smoke_s1" / "default" / "paper" / "sequential-1"
    trajectory = (lost / "CameraTrajectory.txt").read_bytes()
    kept = out / "runs" / "smoke_s2" / "default" / "paper" / "threaded-1" / "run.json"
    kept_time = kept.stat().st_mtime_ns
    subprocess.run(["rm", "-r", str(lost)], check=True)
    os.remove(out / "scores" / "smoke_s1" / "default" / "paper" / "sequential-1.json")
    result = ocg_batch(source_dir, config, "--cores", "2")
    assert result.returncode == 0, result.stderr[-3000:]
    assert (lost / "CameraTrajectory.txt").read_bytes() == trajectory
    assert kept.stat().st_mtime_ns == kept_time
    stats = result.stderr[result.stderr.index("Job stats:"):]
    assert [line.split()[:2] for line in stats.splitlines() if line.startswith("run ")] == \
        [["run", "1"]]
