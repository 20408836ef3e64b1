#!/usr/bin/python3
"""A driveline that no spring ties to ground, recorded as it turns: engine, clutch damper,
gearbox, driveshaft and vehicle with a rolling loss, driven by the engine torque. The
recording starts in motion, twisted and ringing, so no recipe (rest, equilibrium, steady,
measured) gives its start: the proof of `initial_state: { kind: estimated }`
(configs/free_line.yaml). numpy only, independent of tvid: its own equations of motion,
RK4 at 16 steps a sample (scripts/recording_rk4.py).

    scripts/generate_free_line_data.py data/free_line
writes free_line.csv (noisy), free_line_clean.csv and truth.json (the parameters, and the
start as tvid's estimated start holds it: each node's speed, and each angle from the engine's).
"""
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from recording_rk4 import march, write_csv  # noqa: E402

TRUTH = {"J_e": 0.25, "J_g": 0.06, "J_v": 9.0, "k_cl": 600.0, "c_cl": 1.5, "k_ds": 4000.0, "c_ds": 6.0,
         "c_v": 0.9}
FS = 500.0          # samples per second
DURATION = 12.0     # seconds
NOISE_SPEED = 0.05  # rad/s, engine speed sensor
NOISE_TORQUE = 2.0  # N m, shaft torque sensor
# The state when the recording starts: [θ_e, θ_g, θ_v, ω_e, ω_g, ω_v], twisted and not in step.
START = [0.12, 0.035, 0.0, 31.0, 29.5, 30.0]


def engine_torque(t, rng):
    """A tip-in, a back-out and a multisine over a mean drive."""
    tip = 60.0 / (1 + np.exp(-(t - 2.0) / 0.05)) - 70.0 / (1 + np.exp(-(t - 7.0) / 0.08))
    sine = np.zeros_like(t)
    for f in np.arange(0.5, 25.0, 0.75):
        sine += 3.0 * np.sin(2 * np.pi * f * t + rng.uniform(0, 2 * np.pi))
    return 30.0 + tip + sine


def derivative(x, u):
    p = TRUTH
    th_e, th_g, th_v, w_e, w_g, w_v = x
    t_cl = p["k_cl"] * (th_e - th_g) + p["c_cl"] * (w_e - w_g)
    t_ds = p["k_ds"] * (th_g - th_v) + p["c_ds"] * (w_g - w_v)
    return np.array([w_e, w_g, w_v,
                     (u - t_cl) / p["J_e"],
                     (t_cl - t_ds) / p["J_g"],
                     (t_ds - p["c_v"] * w_v) / p["J_v"]])


def shaft_torque(x):
    return TRUTH["k_ds"] * (x[1] - x[2]) + TRUTH["c_ds"] * (x[4] - x[5])


def main():
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "data/free_line")
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(20261127)
    n = int(DURATION * FS) + 1
    t_grid = np.arange(n) / FS
    torque = engine_torque(t_grid, rng)
    t, rows = march(derivative, START, torque, FS, 16, lambda x: [x[3], shaft_torque(x), x[5]])
    w_e, t_ds, w_v = rows[:, 0], rows[:, 1], rows[:, 2]
    header = ["t", "T_engine", "w_engine", "T_shaft", "w_vehicle"]
    write_csv(out / "free_line_clean.csv", header, [t, torque, w_e, t_ds, w_v])
    noisy_w = w_e + rng.normal(0, NOISE_SPEED, n)
    noisy_t = t_ds + rng.normal(0, NOISE_TORQUE, n)
    noisy_v = w_v + rng.normal(0, NOISE_SPEED, n)
    write_csv(out / "free_line.csv", header, [t, torque, noisy_w, noisy_t, noisy_v])
    nodes = ["engine", "gearbox", "vehicle"]
    start = {f"{node}.speed": START[3 + i] for i, node in enumerate(nodes)}
    start.update({f"{node}.angle": START[i] - START[0] for i, node in enumerate(nodes) if i > 0})
    truth = {"parameters": TRUTH, "start": start,
             "noise_std": {"w_engine": NOISE_SPEED, "T_shaft": NOISE_TORQUE, "w_vehicle": NOISE_SPEED},
             "fs_hz": FS, "substeps": 16, "seed": 20261127, "generator": "scripts/generate_free_line_data.py"}
    (out / "truth.json").write_text(json.dumps(truth, indent=1) + "\n")


if __name__ == "__main__":
    main()
