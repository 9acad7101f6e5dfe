"""tools/ocg_batch: the configuration check, the Slurm profile's dry run, a local
two-sequence batch (generated smoke sequences, 20 frames) that resumes after losing a run,
ORB-SLAM2's own settings files, a batch where one run fails in the middle, and
ground-truth-pose runs that read the images when there are some."""
import csv
import json
import os
import subprocess

import pytest

from conftest import run_tool


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
    ("out: o\nsequences: [{preset: smoke, detector: perfect}]\n",
     "sequences[0].detector: expected independent or realistic, got 'perfect'"),
    ("out: o\nsequences: [{path: nowhere, settings: s.yaml}]\n", "sequences[0].path: no such folder"),
    ("out: o\nsequences: [{preset: smoke}]\nvariants: {v: {System.sequential: true}}\n",
     "variants.v.System.sequential: set by executions"),
    # Variant keys are read by the product's own reader, strictly: a misspelt key stops
    # the batch instead of giving a row identical to the default's.
    ("out: o\nsequences: [{preset: smoke}]\nvariants: {v: {LoopClosing.enabeld: false}}\n",
     "variants.v: (defaults): unknown settings keys (no module reads them; docs/settings.md "
     "lists the keys):\n  --set LoopClosing.enabeld: unknown key 'LoopClosing.enabeld'; did you "
     "mean 'LoopClosing.enabled'?"),
    ("out: o\nsequences: [{preset: smoke}]\nvariants: {v: {OCG: {tau_doubt: lots}}}\n",
     "variants.v: --set OCG.tau_doubt: key 'OCG.tau_doubt': expected a number, got 'lots'"),
    ("out: o\nsequences: [{preset: smoke}]\nvariants: {v: {OCG.tau_observable: 1.5}}\n",
     "variants.v: --set OCG.tau_observable: key 'OCG.tau_observable': must be in (0, 1)"),
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
    # Every job of the batch, with the profile's Slurm resources (the tables are made by
    # ocg_batch after the jobs, so that failed runs become rows: no job of their own).
    assert output.count("rule run:") == 6 and output.count("rule sequence:") == 2
    assert output.count("slurm_partition=main") == 19
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


def test_orbslam2_settings_files_and_their_variants_are_read_as_a_run_reads_them(
        source_dir, tools, tmp_path, shared_data):
    """ORB-SLAM2's TUM3 file (OpenCV YAML, "Viewer.PointSize:2") under a sequence folder,
    with a variant: each run's settings file is written by ocg_slam settings."""
    config = write_config(tmp_path, tools, """out: out
sequences:
  - name: fr3
    path: %s/tum_fr3_long_office
    settings: %s/orbslam2_settings/Monocular_TUM3.yaml
    max_frames: 3
variants: {default: {}, no_loops: {LoopClosing: {enabled: false}}}
executions: [sequential]
""" % (shared_data, shared_data))
    result = ocg_batch(source_dir, config, "--cores", "1")
    assert result.returncode == 0, result.stderr[-3000:]
    settings = (tmp_path / "out" / "settings" / "fr3" / "no_loops-sequential.yaml").read_text()
    for line in ("Camera.fx: 535.4", "Viewer.PointSize: 2", "LoopClosing.enabled: false",
                 "System.sequential: true"):
        assert line + "\n" in settings, settings
    # The written file is what ocg_slam reads: checked strictly, it gives TUM3's camera.
    checked = run_tool(tools, "ocg_slam", "settings", str(tmp_path / "out" / "settings" / "fr3" /
                                                           "no_loops-sequential.yaml"),
                       "--strict", "--need-camera")
    assert ": ok" in checked
    rows = read_csv(tmp_path / "out" / "table_II.csv")
    assert [(r["sequence"], r["variant"], r["mode"]) for r in rows] == [
        ("fr3", "default", "slam"), ("fr3", "no_loops", "slam")]


def test_settings_of_another_camera_stop_the_batch_before_any_job(
        source_dir, tools, tmp_path, shared_data):
    config = write_config(tmp_path, tools, """out: out
sequences:
  - path: %s/kitti_07_first160
    settings: %s/orbslam2_settings/Monocular_TUM1.yaml
""" % (shared_data, shared_data))
    result = ocg_batch(source_dir, config, "--cores", "1")
    assert result.returncode != 0
    message = result.stderr
    assert "sequences[0].settings: " in message and "Monocular_TUM1.yaml" in message, message
    assert "640x480" in message and "1226x370" in message, message
    assert sorted(os.listdir(tmp_path)) == ["batch.yaml"]


def test_a_failed_run_is_a_failed_row_and_paths_may_hold_spaces_and_quotes(
        source_dir, tools, tmp_path):
    """Three sequences, one of them with a truncated image at frame 30: its run fails, the
    other two are scored, and the failure is listed with the log's last line. The folders
    and a variant's value hold spaces and quotes: no shell sees them."""
    good = tmp_path / "my data" / "smoke 40"
    bad = tmp_path / "o'brien" / "smoke"
    for folder, seed in ((good, "1"), (bad, "2")):
        run_tool(tools, "ocg_synth", "--preset", "smoke", "--seed", seed, "--frames", "40",
                 "--size", "320x240", "--out", str(folder), "--log-level", "warn")
    frames = [line.split()[1] for line in (bad / "rgb.txt").read_text().splitlines()
              if line.strip() and not line.startswith("#")]
    broken = bad / frames[29]
    broken.write_bytes(broken.read_bytes()[:200])
    vocabulary = tmp_path / "o'brien" / "voc \"1\".ocgvoc"
    vocabulary.symlink_to(os.path.join(source_dir, "thirdparty", "vocabulary",
                                       "ocg_orb_vocabulary.ocgvoc"))
    sequence = """  - path: "%s"
    settings: "%s/camera.yaml"
    detections: "%s/detections"
    objects_gt: "%s/objects_gt.json"
"""
    config = write_config(tmp_path, tools, "out: out\nsequences:\n" +
                          sequence % ((good,) * 4) + sequence % ((bad,) * 4) + """\
  - {preset: smoke, seed: 3, frames: 20, size: 320x240}
modes: [paper]
variants:
  quoted: {Vocabulary.path: '%s'}
executions: [sequential]
""" % str(vocabulary).replace("'", "''"))
    result = ocg_batch(source_dir, config, "--cores", "2")
    assert result.returncode == 3, result.stderr[-3000:]
    out = tmp_path / "out"
    rows = {r["sequence"]: r for r in read_csv(out / "table_II.csv")}
    assert sorted(rows) == ["smoke", "smoke_40", "smoke_s3"]  # names made of the folders'
    assert rows["smoke"]["failed"] == "1"
    for name in ("smoke_40", "smoke_s3"):
        assert rows[name]["failed"] == "0" and float(rows[name]["ate_median_mm"]) < 10.0
    failed = read_csv(out / "failed_runs.csv")
    assert [(f["run"], f["stage"]) for f in failed] == [("smoke/quoted/paper/sequential-1", "run")]
    assert str(broken) in failed[0]["last_log_line"], failed[0]
    table_one = (out / "table_I.md").read_text()
    assert "| smoke | quoted | paper | sequential | 0 | failed |" in table_one, table_one
    assert "- smoke/quoted/paper/sequential-1: run failed: `" in table_one
    # The runs that worked used the vocabulary with the quote in its name.
    run = (out / "runs" / "smoke_40" / "quoted" / "paper" / "sequential-1" / "run.json").read_text()
    assert "voc \\\"1\\\".ocgvoc" in run or "voc \"1\".ocgvoc" in run

    # Run again: only the failed run is redone (and fails again the same way).
    result = ocg_batch(source_dir, config, "--cores", "2")
    assert result.returncode == 3
    stats = result.stderr[result.stderr.index("Job stats:"):]
    assert [line.split()[:2] for line in stats.splitlines() if line.startswith("run ")] == \
        [["run", "1"]]


def slurm_cluster_or_skip(source_dir):
    """The one-node cluster of tools/slurm_local.sh, started when this machine can run it."""
    if os.environ.get("OCG_TEST_SLURM") != "1":
        pytest.skip("the Slurm batch test takes minutes: set OCG_TEST_SLURM=1 to run it "
                    "(it starts the one-node cluster of tools/slurm_local.sh)")
    if os.geteuid() != 0:
        pytest.skip("starting the one-node Slurm cluster needs root (sudo tools/slurm_local.sh "
                    "start), and this test runs as another user")
    if subprocess.run(["which", "slurmctld"], capture_output=True).returncode != 0:
        pytest.skip("slurm-wlm is not installed: sudo tools/slurm_local.sh start installs it")
    started = subprocess.run([os.path.join(source_dir, "tools", "slurm_local.sh"), "start"],
                             capture_output=True, text=True)
    if started.returncode != 0:
        pytest.skip("the one-node Slurm cluster did not start: " + started.stderr[-500:])


def test_batch_through_slurm_matches_the_local_batch_and_failed_jobs_are_rows(
        source_dir, tools, tmp_path):
    """Every job through Slurm (the jobcomp log lists them completed), the tables as a local
    run's (sequential runs are deterministic), and a run that fails is retried once, then is
    a failed row with its Slurm job id."""
    slurm_cluster_or_skip(source_dir)
    bad = tmp_path / "bad"
    run_tool(tools, "ocg_synth", "--preset", "smoke", "--seed", "2", "--frames", "12",
             "--size", "320x240", "--out", str(bad), "--log-level", "warn")
    frames = [line.split()[1] for line in (bad / "rgb.txt").read_text().splitlines()
              if line.strip() and not line.startswith("#")]
    (bad / frames[8]).write_bytes((bad / frames[8]).read_bytes()[:200])
    text = """sequences:
  - {preset: smoke, seed: 1, frames: 20}
  - {path: bad, settings: bad/camera.yaml, detections: bad/detections, objects_gt: bad/objects_gt.json}
modes: [paper, improved]
executions: [sequential]
"""
    local = write_config(tmp_path, tools, "out: local\n" + text)
    os.rename(local, tmp_path / "local.yaml")
    on_slurm = write_config(tmp_path, tools, "out: slurm\n" + text)
    assert ocg_batch(source_dir, str(tmp_path / "local.yaml"), "--cores", "2").returncode == 3
    result = ocg_batch(source_dir, on_slurm, "--profile",
                       os.path.join(source_dir, "eval", "slurm", "local"))
    assert result.returncode == 3, result.stderr[-3000:]
    for table in ("table_I.csv", "table_II.csv"):
        assert (tmp_path / "slurm" / table).read_text() == (tmp_path / "local" / table).read_text()
    # Every job went through Slurm: its log names its job, which Slurm recorded as completed.
    with open("/var/log/slurm/jobcomp.log") as handle:
        states = {line.split("JobId=")[1].split()[0]: line.split("JobState=")[1].split()[0]
                  for line in handle if "JobId=" in line}
    logs = sorted((tmp_path / "slurm" / "logs" / "runs" / "smoke_s1").rglob("*.log"))
    assert len(logs) == 2
    for log in logs:
        job = log.read_text().splitlines()[0].split()[-1]
        assert states.get(job) == "COMPLETED", (log, job)
    # The failing run: tried twice (the profile's restart-times: 1), then a failed row naming
    # its (last) Slurm job and the log's last line.
    failed = read_csv(tmp_path / "slurm" / "failed_runs.csv")
    assert sorted(f["run"] for f in failed) == ["bad/default/improved/sequential-1",
                                               "bad/default/paper/sequential-1"]
    for row in failed:
        assert row["stage"] == "run" and states.get(row["slurm_job"]) == "FAILED", row
        assert "cannot read image" in row["last_log_line"], row
    assert result.stderr.count("Trying to restart job") >= 2, result.stderr[-3000:]


def test_ground_truth_pose_runs_read_the_images_of_a_sequence_that_has_them(
        source_dir, tools, tmp_path):
    """A ground-truth-pose run gets the sequence's frame list when the sequence has images,
    so its objects get their colours (which pair the moves within the session); a
    sequence generated without images runs on the detection files alone."""
    config = write_config(tmp_path, tools, """out: out
sequences:
  - {preset: smoke, seed: 1, frames: 40}
  - {preset: smoke, seed: 2, frames: 40, images: false}
modes: [improved]
variants: {gt: {poses: groundtruth}}
""")
    result = ocg_batch(source_dir, config, "--cores", "2")
    assert result.returncode == 0, result.stderr[-3000:]
    colours = {}
    for name in ("smoke_s1", "smoke_s2"):
        run = tmp_path / "out" / "runs" / name / "gt" / "improved" / "sequential-1"
        with open(run / "run.json") as handle:
            colours[name] = json.load(handle)["colour_signatures"]
    assert colours["smoke_s1"]["keyframe_images"] > 0, colours
    assert colours["smoke_s1"]["sightings"] > 0, colours
    assert colours["smoke_s1"]["unreadable_images"] == 0, colours
    assert colours["smoke_s2"] == {"keyframe_images": 0, "sightings": 0,
                                   "unreadable_images": 0}, colours
