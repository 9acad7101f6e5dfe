"""ocg_eval ate --plot: the PNG of the aligned trajectories (needs matplotlib only)."""
import os
import subprocess

import numpy as np
import pytest

from conftest import run_tool

BLUE = np.array([0x1f, 0x77, 0xb4]) / 255.0  # matplotlib's tab:blue, the estimate


def write_trajectories(folder):
    t = np.linspace(0.0, 10.0, 100)
    gt = np.stack([1000.0 + t, np.cos(t), np.sin(t), 0.1 * t], axis=1)
    est = gt.copy()
    est[:, 0] += 0.003
    est[:, 1:] = 0.5 * gt[:, 1:] + 0.01 * np.sin(7 * t)[:, None]
    for name, rows in (("gt.txt", gt), ("est.txt", est)):
        with open(os.path.join(folder, name), "w") as handle:
            for row in rows:
                handle.write("%.6f %.9f %.9f %.9f 0 0 0 1\n" % tuple(row))


def test_plot_is_written(tools, tmp_path):
    from matplotlib import image
    write_trajectories(tmp_path)
    png = tmp_path / "ate.png"
    output = run_tool(tools, "ocg_eval", "ate", "--gt", str(tmp_path / "gt.txt"), "--est",
                      str(tmp_path / "est.txt"), "--plot", str(png))
    assert "rmse" in output  # the numbers are still printed
    pixels = image.imread(str(png))
    assert pixels.shape[:2] == (700, 1200)
    rgb = pixels[:, :, :3]
    drawn = np.abs(rgb - 1.0).sum(axis=2) > 0.1
    assert drawn.mean() > 0.02, "the plot is (nearly) blank"
    # The aligned estimate is drawn: thousands of pixels in its colour.
    assert (np.abs(rgb - BLUE).sum(axis=2) < 0.1).sum() > 1000
    assert sorted(os.listdir(tmp_path)) == ["ate.png", "est.txt", "gt.txt"]  # no leftovers


def test_missing_matplotlib_is_a_clear_error(tools, tmp_path):
    write_trajectories(tmp_path)
    # A matplotlib that cannot be imported, first on the path.
    fake = tmp_path / "fake" / "matplotlib"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("raise ImportError('no matplotlib here')\n")
    environment = dict(os.environ, PYTHONPATH=str(tmp_path / "fake"))
    png = tmp_path / "ate.png"
    result = subprocess.run([os.path.join(tools, "ocg_eval"), "ate", "--gt",
                             str(tmp_path / "gt.txt"), "--est", str(tmp_path / "est.txt"),
                             "--plot", str(png)], capture_output=True, text=True, env=environment)
    assert result.returncode == 1
    assert "python3-matplotlib" in result.stderr
    assert "ocg_eval: error: --plot" in result.stderr
    assert not png.exists()
    assert result.stdout == ""  # no result printed for a run that failed
