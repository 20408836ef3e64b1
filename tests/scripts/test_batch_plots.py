#!/usr/bin/python3
"""scripts/report_plots/batch.py on batch directories written by hand: with --cross's
matrix (one heatmap per output, a failed cell), without it (the spread alone), and a
directory that is not a batch (no figure). Checks the files and, in the heatmap, the
numbers drawn in the cells.

    test_batch_plots.py SOURCE_DIR WORK_DIR
"""
import csv
import json
import os
import shutil
import sys

source_dir, work_dir = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(source_dir, "scripts"))
from report_plots import batch  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

shutil.rmtree(work_dir, ignore_errors=True)
os.makedirs(work_dir)
ids = ["cycle-2", "cycle-3", "cycle-4", "cycle-5", "cycle-6"]
J = [0.10, 0.11, 0.09, 0.10, 0.50]  # cycle-6 stands out


def write_batch(directory, outputs, cross):
    os.makedirs(directory)
    with open(os.path.join(directory, "batch.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["id", "status", "message", "J", "C", "cost", "evaluations", "verdict", "findings", "wall_seconds"])
        for k, job in enumerate(ids):
            w.writerow([job, "ok", "iteration limit", J[k], 1.0 + 0.01 * k, 1.0, 10, "clean", "", 0.5])
        w.writerow(["cycle-7", "bad_input", "--cycles: cycle 7 is outside the data", "", "", "", "", "", "", 0.0])
    with open(os.path.join(directory, "parameter_stability.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["parameter", "unit", "count", "mean", "std", "cv", "median", "mad", "min", "max", "outliers"])
        w.writerow(["J", "kg m^2", 5, 0.18, 0.18, 1.0, 0.1, 0.01, 0.09, 0.5, "cycle-6"])
        w.writerow(["C", "N m s/rad", 5, 1.02, 0.016, 0.015, 1.02, 0.01, 1.0, 1.04, ""])
    summary = {"experiment": "hand-made", "outliers": [{"id": "cycle-6", "subject": "J", "reason": "J = 0.5 kg m^2"}]}
    if cross:
        summary["outliers"].append({"id": "cycle-4", "subject": "mean_cross_fit", "reason": "low"})
        with open(os.path.join(directory, "matrix_long.csv"), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["fitted", "validated", "output", "fit_percent", "rmse", "status", "problem"])
            for i, a in enumerate(ids):
                for j, b in enumerate(ids):
                    for out in outputs:
                        failed = (a, b) == ("cycle-4", "cycle-6")
                        fit = "" if failed else f"{90 + i - j * 0.5:.4f}"
                        w.writerow([a, b, out, fit, "" if failed else 0.1, "failed" if failed else "ok",
                                    "estimation window cycle 6: diverged" if failed else ""])
    with open(os.path.join(directory, "batch_summary.json"), "w") as f:
        json.dump(summary, f)


failures = []


def expect(condition, message):
    if not condition:
        failures.append(message)


# Captures the texts drawn into the heatmap's cells.
drawn = []
original_text = plt.Axes.text


def recording_text(self, x, y, s, *args, **kwargs):
    drawn.append(s)
    return original_text(self, x, y, s, *args, **kwargs)


plt.Axes.text = recording_text

one = os.path.join(work_dir, "one_output")
write_batch(one, ["omega"], cross=True)
written = batch.draw(one, os.path.join(one, "plots"), 60)
expect(written == ["cross_matrix.png", "parameter_spread.png"], f"one output: {written}")
expect("90.00" in drawn, "the diagonal's first cell, 90 + 0 - 0, is drawn as 90.00")
expect("88.00" in drawn, "cycle-2 on cycle-6 (90 + 0 - 2) is drawn as 88.00")
expect("failed" in drawn, "the failed cell says so")
expect(len(drawn) == 25, f"one text per cell of the 5 x 5 matrix, got {len(drawn)}")

two = os.path.join(work_dir, "two_outputs")
write_batch(two, ["omega", "torque"], cross=True)
written = batch.draw(two, os.path.join(two, "plots"), 60)
expect(written == ["cross_matrix_omega.png", "cross_matrix_torque.png", "parameter_spread.png"],
       f"two outputs: {written}")

plain = os.path.join(work_dir, "no_cross")
write_batch(plain, ["omega"], cross=False)
written = batch.draw(plain, os.path.join(plain, "plots"), 60)
expect(written == ["parameter_spread.png"], f"without --cross: {written}")

expect(batch.draw(source_dir, os.path.join(work_dir, "none"), 60) == [], "a directory without batch.csv")

for directory in (one, two, plain):
    for name in os.listdir(os.path.join(directory, "plots")):
        with open(os.path.join(directory, "plots", name), "rb") as f:
            expect(f.read(8) == b"\x89PNG\r\n\x1a\n", f"{name} is a PNG")

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("batch plots: ok")
