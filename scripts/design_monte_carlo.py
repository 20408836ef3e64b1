#!/usr/bin/env python3
"""Checks `tvid design`'s predicted standard errors against the spread of real fits, on a
shipped example with an independent generator: each candidate input of a design report is
played through the example's generator (scripts/generate_EXAMPLE_data.py: its own equations
and RK4, independent of tvid) at the true parameters, white noise of the design's standard
deviations is added with SEEDS seeds, and `tvid fit` fits each record with the shipped
experiment (its model, parameters, init and integrator), every output weighted by 1/sigma
(weight: 1/sigma, normalize: none): the fit the prediction is for. Prints, per candidate and
parameter, the predicted standard error, the fitted values' standard deviation, their ratio
and the mean's offset from the truth in standard errors; writes monte_carlo.json.

    /usr/bin/python3 scripts/design_monte_carlo.py REPORT_DIR --example driveline|clutch_damper
        [--seeds 20] [--tvid PATH] [--candidates designed,chirp] [--work DIR]

REPORT_DIR is the output of `tvid design configs/EXAMPLE.yaml --params TRUTH.json -o REPORT_DIR
--set 'design={...}'` with TRUTH.json the parameters of data/EXAMPLE/truth.json. numpy only.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import generate_clutch_damper_data as clutch_damper  # noqa: E402
import generate_driveline_data as driveline  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def driveline_outputs(te):
    _, rows = driveline.simulate(driveline.TRUTH, te)
    return {"w_engine": rows[:, 0], "w_wheel": rows[:, 1], "T_shaft": rows[:, 2]}


def clutch_damper_outputs(te):
    _, w1, w2, _ = clutch_damper.simulate(clutch_damper.TRUTH, te)
    return {"w1": w1, "w2": w2}


# Each example: its generator's sample rate and clean outputs for an engine torque, its
# shipped experiment, and its input's column.
EXAMPLES = {
    "driveline": (driveline.FS, driveline_outputs, "configs/driveline.yaml", "T_engine"),
    "clutch_damper": (clutch_damper.FS, clutch_damper_outputs, "configs/clutch_damper.yaml", "T_engine"),
}


def write_record(path, t, column, te, outputs):
    names = ["t", column] + list(outputs)
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        for i in range(t.size):
            f.write(",".join(f"{v:.12g}" for v in [t[i], te[i]] + [outputs[k][i] for k in outputs]) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("report")
    ap.add_argument("--example", required=True, choices=sorted(EXAMPLES))
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--tvid", default=os.path.join(ROOT, "build", "release", "apps", "tvid", "tvid"))
    ap.add_argument("--candidates", default="")
    ap.add_argument("--work", default="")
    args = ap.parse_args()
    with open(os.path.join(args.report, "design.json")) as f:
        design = json.load(f)
    noise = {k: v["sigma"] for k, v in design["assumptions"]["noise"].items()}
    work = args.work or os.path.join(args.report, "monte_carlo")
    os.makedirs(work, exist_ok=True)
    wanted = [c for c in args.candidates.split(",") if c]
    rows = []
    fs, clean_outputs, config, column = EXAMPLES[args.example]
    for cand in design["candidates"]:
        if cand["file"] is None or (wanted and cand["name"] not in wanted):
            continue
        data = np.loadtxt(os.path.join(args.report, cand["file"]), delimiter=",", skiprows=1)
        t, te = data[:, 0], data[:, 1]
        if abs((t[1] - t[0]) * fs - 1) > 1e-9:
            sys.exit(f"{cand['file']}: the generator runs at {fs:g} Hz")
        clean = clean_outputs(te)
        fitted, failed = [], []
        for seed in range(1, args.seeds + 1):
            rng = np.random.default_rng(1000 + seed)
            record = os.path.abspath(os.path.join(work, f"{cand['name']}_{seed}.csv"))
            write_record(record, t, column, te, {k: v + rng.normal(0, noise[k], t.size) for k, v in clean.items()})
            out = os.path.join(work, f"{cand['name']}_{seed}_fit")
            command = [args.tvid, "fit", os.path.join(ROOT, config), "-o", out, "--force", "--quiet",
                       "--set", f"data={{ file: {record}, time: t }}",
                       "--set", f"windows={{ estimation: [ {{ time: [0, {float(t[-1])!r}] }} ] }}",
                       "--set", "estimation.normalize=none"]
            for k in noise:
                command += ["--set", f"outputs.{k}.weight={1.0 / noise[k]!r}"]
            subprocess.run(command, check=True)
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            # A fit that did not converge (LM's iteration limit far from the optimum) is a
            # failure of the search, not a sample of the spread at the optimum: counted apart.
            if not summary["optimizer"]["converged"]:
                failed.append(seed)
                continue
            fitted.append({p["name"]: p["value"] for p in summary["parameters"]})
        print(f"{cand['name']}: {len(fitted)} of {args.seeds} fits converged"
              + (f" (not: seeds {', '.join(map(str, failed))})" if failed else ""))
        for p in cand["parameters"]:
            values = np.array([v[p["name"]] for v in fitted])
            spread = float(np.std(values, ddof=1))
            rows.append((cand["name"], p["name"], p["nominal"], p["se"], spread, spread / p["se"],
                         float(np.mean(values) - p["nominal"]) / p["se"]))
    print(f"{'candidate':10s} {'parameter':9s} {'truth':>10s} {'predicted se':>13s} {'fitted sd':>11s} "
          f"{'sd/se':>6s} {'bias/se':>8s}")
    for r in rows:
        print(f"{r[0]:10s} {r[1]:9s} {r[2]:10.4g} {r[3]:13.4g} {r[4]:11.4g} {r[5]:6.2f} {r[6]:8.2f}")
    with open(os.path.join(work, "monte_carlo.json"), "w") as f:
        json.dump([dict(zip(("candidate", "parameter", "truth", "predicted_se", "fitted_sd", "ratio", "bias_in_se"), r))
                   for r in rows], f, indent=1)


if __name__ == "__main__":
    main()
