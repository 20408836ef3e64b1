#!/usr/bin/env python3
"""A recording of one shaft against dry friction, made independently of tvid: its own
equations written out here and its own fixed-step RK4 (10 substeps a sample), numpy only.

A shaft (J) is driven by a measured torque T_m, a multi-sine around zero whose amplitude is
well above the breakaway torque, so the shaft reverses often and sometimes passes slowly
through zero speed. It turns against friction to ground, viscous and dry with a Stribeck
rise, each different in the two directions (tvid's `friction` law with the sign smoothed):

    v = w,  s = tanh(v / v_s),  p = (1 + s)/2
    c_eff = c_negative + (c - c_negative) p,   F_eff = coulomb_negative + (coulomb - coulomb_negative) p
    T_f = c_eff v + (F_eff + (breakaway - coulomb) exp(-(v / stribeck_speed)^2)) s
    J w' = T_m - T_f

with v_s = 0.05 rad/s. The recorded output is the speed w. Written: dry_friction_clean.csv
(no noise) and dry_friction.csv (noise on w), truth.json with the parameters.

    /usr/bin/python3 scripts/generate_dry_friction_data.py [OUT_DIR]      (default data/dry_friction)
"""
import json
import os
import sys

import numpy as np

from recording_rk4 import march, write_csv

TRUTH = {"J": 0.05, "c": 0.2, "c_negative": 0.3, "coulomb": 2.0, "coulomb_negative": 1.4,
         "breakaway": 4.0, "stribeck_speed": 1.5}
SMOOTHING_SPEED = 0.05   # rad/s, a constant of the model
FS = 1000.0              # samples per second
DURATION = 5.0           # s
SUBSTEPS = 10
NOISE = {"w": 0.02}      # rad/s
SEED = 20261128


def drive_torque(t):
    """A multi-sine of 0.6-8.9 Hz around zero, peaks of about 12 N m."""
    rng = np.random.default_rng(3)
    freqs = np.array([0.6, 1.3, 2.1, 3.4, 5.5, 8.9])
    amps = np.array([4.0, 3.5, 3.0, 2.0, 1.5, 1.0])
    phases = rng.uniform(0, 2 * np.pi, freqs.size)
    t = np.asarray(t, dtype=float)
    return np.sum(amps[:, None] * np.sin(2 * np.pi * freqs[:, None] * t[None, :] + phases[:, None]), axis=0)


def friction(v, p):
    s = np.tanh(v / SMOOTHING_SPEED)
    q = 0.5 * (1.0 + s)
    c_eff = p["c_negative"] + (p["c"] - p["c_negative"]) * q
    f_eff = p["coulomb_negative"] + (p["coulomb"] - p["coulomb_negative"]) * q
    rise = p["breakaway"] - p["coulomb"]
    return c_eff * v + (f_eff + rise * np.exp(-(v / p["stribeck_speed"]) ** 2)) * s


def derivative(x, tm, p):
    th, w = x
    return np.array([w, (tm - friction(w, p)) / p["J"]])


def simulate(p, tm_samples):
    t, rows = march(lambda x, u: derivative(x, u, p), np.zeros(2), tm_samples, FS, SUBSTEPS,
                    lambda x: (x[1],))
    return t, rows[:, 0]


def write(path, t, tm, w):
    write_csv(path, ["t", "T_m", "w"], [t, tm, w])


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "dry_friction")
    os.makedirs(out, exist_ok=True)
    tm_samples = drive_torque(np.arange(int(round(DURATION * FS)) + 1) / FS)
    t, w = simulate(TRUTH, tm_samples)
    write(os.path.join(out, "dry_friction_clean.csv"), t, tm_samples, w)
    rng = np.random.default_rng(SEED)
    write(os.path.join(out, "dry_friction.csv"), t, tm_samples, w + rng.normal(0, NOISE["w"], t.size))
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "constants": {"smoothing_speed": SMOOTHING_SPEED}, "noise_std": NOISE,
                   "fs_hz": FS, "substeps": SUBSTEPS, "seed": SEED,
                   "generator": "scripts/generate_dry_friction_data.py"}, f, indent=1)
    print(f"wrote {out}: {t.size} samples; speed {w.min():.2f} ... {w.max():.2f} rad/s, "
          f"{np.sum(np.diff(np.sign(w[np.abs(w) > 0.01])) != 0)} reversals")
