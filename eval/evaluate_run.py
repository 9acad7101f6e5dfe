"""Scores one run of the batch: ATE (ocg_eval ate --json, and its --plot for the top view
of the estimate against the ground truth) and the object metrics of Table I
(ocg_eval objects --json). A run that failed to track (no trajectory, too few poses)
is recorded as such instead of stopping the batch.

Usage: evaluate_run.py TOOLS RUN_DIR OUT.json OUT.png GROUNDTRUTH|- OBJECTS_GT|- MAX_DT
"""
import json
import os
import subprocess
import sys


def ocg_eval(tools, *arguments):
    result = subprocess.run([os.path.join(tools, "ocg_eval"), *arguments], capture_output=True,
                            text=True)
    if result.returncode != 0:
        return None, (result.stderr.strip().splitlines() or ["ocg_eval failed"])[-1]
    return json.loads(result.stdout), None


def blank_plot(path, message):
    """The run's plot when there is nothing to draw, so that every run has one."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot
    figure = pyplot.figure(figsize=(6, 3), dpi=100)
    figure.text(0.5, 0.5, message, ha="center", va="center", wrap=True)
    figure.savefig(path)
    pyplot.close(figure)


def main():
    if len(sys.argv) != 8:
        sys.exit(__doc__)
    tools, run_dir, out_json, out_png, groundtruth, objects_gt, max_dt = sys.argv[1:]
    report = {"run": run_dir}
    with open(os.path.join(run_dir, "run.json")) as handle:
        run = json.load(handle)
    report["frames"] = run.get("frames")
    report["frames_tracked"] = run.get("frames_tracked")
    report["keyframes"] = run.get("keyframes")
    report["loops"] = len(run.get("loop_closing", {}).get("loops", []))
    report["tracking_ms"] = run.get("timing", {}).get("tracking_per_frame", {}).get("median_ms")
    trajectory = os.path.join(run_dir, "CameraTrajectory.txt")
    if groundtruth != "-":
        report["ate"], report["ate_error"] = ocg_eval(
            tools, "ate", "--gt", groundtruth, "--est", trajectory, "--align", "sim3",
            "--max-dt", max_dt, "--json", "--plot", out_png)
        if objects_gt != "-" and os.path.exists(os.path.join(run_dir, "objects.json")):
            report["objects"], report["objects_error"] = ocg_eval(
                tools, "objects", "--gt", objects_gt, "--run", run_dir, "--groundtruth",
                groundtruth, "--json")
    else:
        report["ate"], report["ate_error"] = None, "no ground-truth trajectory"
    if not os.path.exists(out_png):
        blank_plot(out_png, "%s\nno ATE: %s" % (run_dir, report["ate_error"]))
    temporary = out_json + ".tmp"
    with open(temporary, "w") as handle:
        json.dump(report, handle, indent=1)
    os.replace(temporary, out_json)


if __name__ == "__main__":
    main()
