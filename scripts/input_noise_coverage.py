#!/usr/bin/env python3
"""Do the standard errors hold with a noisy logged input? The rigid_gear launch
(generate_rigid_gear_data.py: numpy, its own RK4) is recorded anew with SEEDS new noise
draws: the three outputs' sensor noise and 1.5 N m of white noise on the logged engine
torque. Each recording is fitted by `tvid fit` with configs/rigid_gear_noisy_input.yaml
(noise: 1.5 declared), or without the declaration (--undeclared). Printed per parameter: the
spread of the estimates over the mean std_error (about 1 when they hold), and the largest
|error| over std_error and over robust_std_error; then the verdict's findings.

    /usr/bin/python3 scripts/input_noise_coverage.py [--seeds 12] [--undeclared] [--tvid build/release/apps/tvid/tvid]
"""
import argparse
import collections
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import generate_rigid_gear_data as g  # noqa: E402
from recording_rk4 import write_csv  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=12)
    ap.add_argument("--undeclared", action="store_true")
    ap.add_argument("--tvid", default=os.path.join(HERE, "..", "build", "release", "apps", "tvid", "tvid"))
    args = ap.parse_args()
    te = g.engine_torque(np.arange(int(round(g.DURATION * g.FS)) + 1) / g.FS)
    t, w_e, w_v, t_s, _ = g.simulate(g.TRUTH, te)
    config = open(os.path.join(HERE, "..", "configs", "rigid_gear_noisy_input.yaml")).read()
    if args.undeclared:
        config = config.replace(", noise: 1.5", "")
    rows, findings = [], collections.Counter()
    with tempfile.TemporaryDirectory() as work:
        for seed in range(args.seeds):
            rng = np.random.default_rng(1000 + seed)
            noise = g.NOISE
            outputs = (w_e + rng.normal(0, noise["w_engine"], t.size), w_v + rng.normal(0, noise["w_wheel"], t.size),
                       t_s + rng.normal(0, noise["T_shaft"], t.size))
            logged = te + rng.normal(0, g.INPUT_NOISE["T_engine_logged"], t.size)
            folder = os.path.join(work, f"seed{seed}")
            os.makedirs(folder)
            csv = os.path.join(folder, "rigid_gear.csv")
            write_csv(csv, ["t", "T_engine", "w_engine", "w_wheel", "T_shaft", "T_engine_logged"], [t, te, *outputs, logged])
            experiment = os.path.join(folder, "experiment.yaml")
            with open(experiment, "w") as f:
                f.write(config.replace("../data/rigid_gear/rigid_gear.csv", csv))
            run = subprocess.run([args.tvid, "fit", experiment, "-o", os.path.join(folder, "out"), "--json", "--quiet"],
                                 capture_output=True, text=True, check=True)
            summary = json.loads(run.stdout)
            rows.append({p["name"]: (p["value"], p["std_error"], p["robust_std_error"]) for p in summary["parameters"]})
            for finding in summary["verdict"]["findings"]:
                findings[(finding["severity"], finding["code"])] += 1
    print(f"{'parameter':9} {'truth':>9} {'mean':>10} {'spread':>9} {'mean SE':>9} {'spread/SE':>9} "
          f"{'max|err|/SE':>11} {'max|err|/robust':>15}")
    for name, truth in g.TRUTH.items():
        value = np.array([r[name][0] for r in rows])
        se = np.array([r[name][1] for r in rows])
        robust = np.array([r[name][2] for r in rows])
        error = np.abs(value - truth)
        print(f"{name:9} {truth:9.4g} {value.mean():10.5g} {value.std(ddof=1):9.3g} {se.mean():9.3g} "
              f"{value.std(ddof=1) / se.mean():9.2f} {np.max(error / se):11.2f} {np.max(error / robust):15.2f}")
    print(f"verdict findings over {args.seeds} recordings: " +
          (", ".join(f"{n} {s} {c}" for (s, c), n in sorted(findings.items())) or "none"))


if __name__ == "__main__":
    main()
