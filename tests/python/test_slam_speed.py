"""bench/slam_speed.py, short: the figures it prints come from the run it made, its
settings overrides reach the run, and bad input fails before any work with a message."""
import json
import os
import subprocess
import sys

import pytest


def bench(source_dir, tools, *arguments):
    return subprocess.run(
        [sys.executable, os.path.join(source_dir, "bench", "slam_speed.py"),
         "--build", os.path.dirname(tools), *arguments],
        capture_output=True, text=True)


def test_a_short_threaded_run_reports_its_own_figures(source_dir, tools, tmp_path):
    figures_path = tmp_path / "figures.json"
    result = bench(source_dir, tools, "--preset", "smoke", "--frames", "25", "--threaded",
                   "--features", "600", "--cores", "1", "--json", str(figures_path),
                   "--keep", str(tmp_path / "run"))
    assert result.returncode == 0, result.stderr
    figures = json.loads(figures_path.read_text())
    run = json.loads((tmp_path / "run" / "slam" / "run.json").read_text())
    # The overrides reached the run: threaded mode and 600 features.
    assert figures["mode"] == "threaded" == run["mode"]
    assert run["orb"]["features"] == 600 == figures["features"]
    assert figures["cores"] == 1
    assert figures["frames"] == 25
    assert figures["timing"] == run["timing"]
    assert figures["timing"]["tracking_per_frame"]["count"] == 25
    assert "tracking per frame" in result.stdout
    assert f"{figures['frames_tracked']} of 25 frames tracked" in result.stdout


def test_an_existing_flat_key_is_replaced_not_given_twice(source_dir, tools, tmp_path):
    # An ORB-SLAM2-style file with the flat keys already there: a second line would be
    # refused by the settings reader as a key given twice.
    sequence = tmp_path / "seq"
    subprocess.run([os.path.join(tools, "ocg_synth"), "--preset", "smoke", "--frames", "12",
                    "--out", str(sequence), "--keyframe-interval", "0", "--log-level", "warn"],
                   check=True, capture_output=True)
    settings = tmp_path / "settings.yaml"
    settings.write_text((sequence / "camera.yaml").read_text() +
                        "ORBextractor.nFeatures: 1000\nSystem.sequential: false\n")
    figures_path = tmp_path / "figures.json"
    result = bench(source_dir, tools, "--sequence", str(sequence), "--settings", str(settings),
                   "--features", "700", "--json", str(figures_path))
    assert result.returncode == 0, result.stderr
    figures = json.loads(figures_path.read_text())
    assert figures["features"] == 700
    assert figures["mode"] == "sequential"


@pytest.mark.parametrize("arguments, message", [
    (["--sequence", "/nonexistent"], "--sequence needs --settings"),
    (["--sequence", "/nonexistent", "--settings", "/nonexistent.yaml"], "no rgb.txt"),
    (["--preset", "smoke", "--cores", "999"], "only"),
])
def test_bad_input_fails_with_a_message(source_dir, tools, arguments, message):
    result = bench(source_dir, tools, *arguments)
    assert result.returncode != 0
    assert message in result.stderr
