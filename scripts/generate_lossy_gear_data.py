#!/usr/bin/env python3
"""A recording of a motor driving and braking a load through a lossy gear, made independently
of tvid: its own equations written out here and its own fixed-step RK4 (10 substeps a
sample), numpy only.

A motor (J1) is driven by a measured torque that accelerates and brakes in turn, so the power
through the gear flows both ways. The gear (tvid's `gear_mesh` with `efficiency`: ratio n = 3,
mesh stiffness k and damping c on the input side) passes its torque to the load (J2) with the
efficiency eta in the direction the power flows, smoothed over 1 W:

    T = k (th1 - n th2) + c (w1 - n w2),   P = T w1,   f = eta ** tanh(P / 1 W)
    J1 w1' = T_m - T,   J2 w2' = n T f - c2 w2

The recorded outputs are the load's speed and the torque of a transducer on the output shaft,
n T f. Written: lossy_gear_clean.csv (no noise) and lossy_gear.csv (noise on the two
outputs), truth.json with the parameters.

    /usr/bin/python3 scripts/generate_lossy_gear_data.py [OUT_DIR]      (default data/lossy_gear)
"""
import json
import os
import sys

import numpy as np

from recording_rk4 import march, write_csv

TRUTH = {"J1": 0.01, "J2": 0.3, "k": 2000.0, "c": 0.8, "eta": 0.9, "c2": 0.3}
RATIO = 3.0
SMOOTHING_POWER = 1.0   # W, a constant of the model
FS = 1000.0             # samples per second
DURATION = 5.0          # s
SUBSTEPS = 10
NOISE = {"w2": 0.02, "T_out": 0.1}   # rad/s, N m
SEED = 20261201


def motor_torque(t):
    """A mean of 3 N m, a swing of +-8 N m at 0.8 Hz between driving and braking, and a
    multi-sine of 3-80 Hz that rings the mesh (its mode is near 80 Hz)."""
    rng = np.random.default_rng(13)
    freqs = np.array([3.0, 5.5, 9.0, 14.0, 21.0, 33.0, 47.0, 60.0, 80.0])
    phases = rng.uniform(0, 2 * np.pi, freqs.size)
    t = np.asarray(t, dtype=float)
    ripple = 2.0 * np.sum(np.sin(2 * np.pi * freqs[:, None] * t[None, :] + phases[:, None]), axis=0) / 3.0
    return 3.0 + 8.0 * np.sin(2 * np.pi * 0.8 * t) + ripple


def mesh(x, p):
    """The mesh torque T on the input shaft and the torque n T f on the output shaft."""
    th1, th2, w1, w2 = x
    T = p["k"] * (th1 - RATIO * th2) + p["c"] * (w1 - RATIO * w2)
    f = p["eta"] ** np.tanh(T * w1 / SMOOTHING_POWER)
    return T, RATIO * T * f


def derivative(x, tm, p):
    T, T_out = mesh(x, p)
    return np.array([x[2], x[3], (tm - T) / p["J1"], (T_out - p["c2"] * x[3]) / p["J2"]])


def simulate(p, tm_samples):
    t, rows = march(lambda x, u: derivative(x, u, p), np.zeros(4), tm_samples, FS, SUBSTEPS,
                    lambda x: (lambda T, T_out: (x[3], T_out, T * x[2]))(*mesh(x, p)))  # w2, n T f, power T w1
    return t, rows[:, 0], rows[:, 1], rows[:, 2]


def write(path, t, tm, w2, t_out):
    write_csv(path, ["t", "T_motor", "w2", "T_out"], [t, tm, w2, t_out])


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "lossy_gear")
    os.makedirs(out, exist_ok=True)
    tm_samples = motor_torque(np.arange(int(round(DURATION * FS)) + 1) / FS)
    t, w2, t_out, power = simulate(TRUTH, tm_samples)
    write(os.path.join(out, "lossy_gear_clean.csv"), t, tm_samples, w2, t_out)
    rng = np.random.default_rng(SEED)
    write(os.path.join(out, "lossy_gear.csv"), t, tm_samples, w2 + rng.normal(0, NOISE["w2"], t.size),
          t_out + rng.normal(0, NOISE["T_out"], t.size))
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "constants": {"ratio": RATIO, "smoothing_power": SMOOTHING_POWER},
                   "noise_std": NOISE, "fs_hz": FS, "substeps": SUBSTEPS, "seed": SEED,
                   "generator": "scripts/generate_lossy_gear_data.py"}, f, indent=1)
    print(f"wrote {out}: {t.size} samples; load speed {w2.min():.2f} ... {w2.max():.2f} rad/s, "
          f"power through the gear {power.min():.0f} ... {power.max():.0f} W, "
          f"{100 * np.mean(power < 0):.0f} % of the time flowing back")
