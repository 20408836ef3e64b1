#!/usr/bin/python3
"""How a window's start shapes a fit, on the free line of configs/free_line.yaml (a line not
tied to ground recorded in motion, data/free_line/truth.json): three reports of `tvid fit`,
the same recording and model with three starts, drawn side by side (numpy and matplotlib):

  top:    the vehicle speed's residual over the estimation window of each (the slow
          rigid-body mode keeps a start's speed error longest);
  bottom: each parameter's distance from the truth, in its own standard errors.

    tvid fit configs/free_line.yaml -o results/start-estimated
    tvid fit configs/free_line.yaml --set initial_state=measured -o results/start-measured
    tvid fit configs/free_line.yaml --set initial_state=measured --set windows.warmup=2 \\
        --set 'windows.estimation=[{time: [2, 8]}]' -o results/start-warmup
    /usr/bin/python3 scripts/plot_start_choices.py results/start-measured results/start-warmup \\
        results/start-estimated [OUT.png]          (default docs/images/start_choices.png)
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

LABELS = ["measured (untwisted)", "measured, 2 s warm-up", "estimated"]
COLOURS = ["tab:red", "tab:orange", "tab:blue"]


def read_trace(report, column):
    """Time and one column of a report's estimation.csv (its heading without the unit)."""
    with open(os.path.join(report, "estimation.csv")) as f:
        header = f.readline().strip().split(",")
    names = [h.split(" [")[0] for h in header]
    data = np.genfromtxt(os.path.join(report, "estimation.csv"), delimiter=",", skip_header=1,
                         usecols=(0, names.index(column)))
    return data[:, 0], data[:, 1]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    reports = sys.argv[1:4]
    out = sys.argv[4] if len(sys.argv) > 4 else os.path.join("docs", "images", "start_choices.png")
    here = os.path.dirname(os.path.abspath(__file__))
    truth = json.load(open(os.path.join(here, "..", "data", "free_line", "truth.json")))["parameters"]
    names = list(truth)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 7.5), gridspec_kw={"height_ratios": [1.2, 1]})
    width = 0.8 / len(reports)
    for k, (report, label, colour) in enumerate(zip(reports, LABELS, COLOURS)):
        t, r = read_trace(report, "w_vehicle_residual")
        top.plot(t, r, color=colour, lw=0.8, label=label, alpha=0.85)
        params = {p["name"]: p for p in json.load(open(os.path.join(report, "params.json")))["parameters"]}
        sigmas = [(params[n]["value"] - truth[n]) / params[n]["std_error"] if params[n]["std_error"] else np.nan
                  for n in names]
        bottom.bar(np.arange(len(names)) + (k - 1) * width, np.clip(sigmas, -30, 30), width, color=colour,
                   label=label)
    top.set_xlabel("time [s]")
    top.set_ylabel("w_vehicle residual [rad/s]")
    top.set_title("vehicle speed residual over the estimation window (noise: 0.05 rad/s)")
    top.legend(loc="upper right")
    bottom.axhspan(-3, 3, color="0.85", zorder=0, label="within 3 standard errors")
    bottom.set_xticks(np.arange(len(names)), names)
    bottom.set_ylabel("(fit − truth) / std error")
    bottom.set_title("each parameter from the truth, in its standard errors (clipped at ±30)")
    bottom.legend(loc="upper left", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
