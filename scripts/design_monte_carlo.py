#!/usr/bin/env python3
"""Checks `tvid design --evaluate`'s predicted standard errors on the shipped driveline
(configs/driveline.yaml) against the spread of real fits: each candidate input of a design
report is played through scripts/generate_driveline_data.py (its own equations and RK4,
independent of tvid) at the true parameters, white noise of the design's standard deviations
is added with SEEDS seeds, and `tvid fit` fits each record by LM from the shipped init
(25-35 % off the truth), every output weighted by 1/sigma (weight: 1/sigma, normalize: none),
the fit the prediction is for. Prints, per candidate and parameter, the predicted standard
error, the fitted values' standard deviation and their ratio.

    /usr/bin/python3 scripts/design_monte_carlo.py REPORT_DIR [--seeds 20] [--tvid PATH]
        [--candidates multisine,chirp] [--work DIR]

REPORT_DIR is the output of
    tvid design configs/driveline.yaml --evaluate --params TRUTH.json -o REPORT_DIR --set 'design={...}'
with TRUTH.json the parameters of data/driveline/truth.json. numpy only.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import generate_driveline_data as driveline  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")

MODEL = """model:
  nodes:
    - { name: engine, J: 0.2 }
    - { name: gear_in, J: 0.015 }
    - { name: gear_out, J: 0.005 }
    - { name: wheel, J: Jv }
  elements:
    - { type: torque, name: drive, node: engine, input: T_engine }
    - { type: multistage_spring, name: damper, between: [engine, gear_in],
        stages: [ { angle: 0, k: k1 }, { angle: 0.06, k: k2 } ], c: c_d, smoothing_angle: 0.002 }
    - { type: friction, name: hysteresis, between: [engine, gear_in], coulomb: Fh, smoothing_speed: 0.01 }
    - { type: ideal_gear, name: gearbox, between: [gear_in, gear_out], ratio: 3.5, efficiency: 0.93 }
    - { type: spring_damper, name: halfshaft, between: [gear_out, wheel], k: ks, c: ds }
    - { type: road_load, name: road, node: wheel, a: a, c: c_air, smoothing_speed: 0.1 }
inputs: { T_engine: T_engine }
parameters:
  k1:    { init: 650,    min: 1,      max: 1.0e5 }
  k2:    { init: 1400,   min: 1,      max: 1.0e5 }
  c_d:   { init: 2.0,    min: 0,      max: 100 }
  Fh:    { init: 5.6,    min: 0,      max: 100 }
  ks:    { init: 9000,   min: 1,      max: 1.0e6 }
  ds:    { init: 27,     min: 0,      max: 1000 }
  a:     { init: 65,     min: 0,      max: 1000 }
  c_air: { init: 0.0085, min: 0,      max: 1 }
  Jv:    { init: 75,     min: 1,      max: 1.0e4 }
initial_state: rest
simulation: { method: sdirk3, step: sample }
estimation: { cost: l2, optimizer: lm, normalize: none }
"""


def experiment(record, noise, t_end):
    out = "outputs:\n"
    for name, speed in (("w_engine", "speed: engine"), ("w_wheel", "speed: wheel"), ("T_shaft", "torque: halfshaft")):
        out += f"  {name}: {{ column: {name}, {speed}, weight: {1.0 / noise[name]!r} }}\n"
    return (f"tvid: 1\nname: design-check\ndata: {{ file: {os.path.basename(record)}, time: t }}\n" + MODEL + out +
            f"windows: {{ estimation: [ {{ time: [0, {t_end!r}] }} ] }}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("report")
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
    for cand in design["candidates"]:
        if cand["file"] is None or (wanted and cand["name"] not in wanted):
            continue
        data = np.loadtxt(os.path.join(args.report, cand["file"]), delimiter=",", skiprows=1)
        t, te = data[:, 0], data[:, 1]
        if abs((t[1] - t[0]) * driveline.FS - 1) > 1e-9:
            sys.exit(f"{cand['file']}: the generator runs at {driveline.FS:g} Hz")
        _, clean = driveline.simulate(driveline.TRUTH, te)
        fitted = []
        for seed in range(1, args.seeds + 1):
            rng = np.random.default_rng(1000 + seed)
            record = os.path.join(work, f"{cand['name']}_{seed}.csv")
            driveline.write(record, t, te, clean[:, 0] + rng.normal(0, noise["w_engine"], t.size),
                            clean[:, 1] + rng.normal(0, noise["w_wheel"], t.size),
                            clean[:, 2] + rng.normal(0, noise["T_shaft"], t.size))
            config = os.path.join(work, f"{cand['name']}_{seed}.yaml")
            with open(config, "w") as f:
                f.write(experiment(record, noise, float(t[-1])))
            out = os.path.join(work, f"{cand['name']}_{seed}_fit")
            subprocess.run([args.tvid, "fit", config, "-o", out, "--force", "--quiet"], check=True)
            with open(os.path.join(out, "summary.json")) as f:
                fitted.append({p["name"]: p["value"] for p in json.load(f)["parameters"]})
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
