#!/usr/bin/env python3
"""A recording of a vehicle driven up to speed against its road load, made independently of
tvid: its own equations written out here and its own fixed-step RK4 (10 substeps a sample),
numpy only.

A motor (J1) drives the vehicle's inertia at the wheels (J2) through a shaft (k, c). The
vehicle turns against the road load (tvid's `road_load` law: rolling resistance smoothed
through zero speed, a linear and an aerodynamic term)

    T_road = a tanh(w2 / v_s) + b w2 + c_air w2 |w2|,      v_s = 0.1 rad/s

The motor torque is measured: full torque from rest to about 100 rad/s, a coast with the
motor torque at zero, a second, gentler acceleration and a second coast, with a multi-sine of
2-40 Hz on it throughout that rings the shaft. The recorded outputs are the vehicle's speed
and the shaft torque. Written: road_load_clean.csv (no noise) and road_load.csv (noise on
the two outputs), truth.json with the parameters.

    /usr/bin/python3 scripts/generate_road_load_data.py [OUT_DIR]      (default data/road_load)
"""
import json
import os
import sys

import numpy as np

from recording_rk4 import march, write_csv

TRUTH = {"J1": 0.1, "J2": 1.2, "k": 1500.0, "c": 3.0, "a": 6.0, "b": 0.08, "c_air": 0.003}
SMOOTHING_SPEED = 0.1   # rad/s, a constant of the model
FS = 1000.0             # samples per second
DURATION = 6.0          # s
SUBSTEPS = 10
NOISE = {"w2": 0.05, "T_shaft": 0.2}   # rad/s, N m
SEED = 20261130


def motor_torque(t):
    """The driving pattern (ramps of 0.1 s between its levels) with a multi-sine of 2-40 Hz on it."""
    pattern_t = [0.0, 0.1, 2.2, 2.3, 3.5, 3.6, 4.6, 4.7]
    pattern_T = [0.0, 80.0, 80.0, 0.0, 0.0, 40.0, 40.0, 0.0]
    rng = np.random.default_rng(11)
    freqs = np.array([2.0, 3.5, 5.0, 7.5, 11.0, 16.0, 23.0, 31.0, 40.0])
    phases = rng.uniform(0, 2 * np.pi, freqs.size)
    t = np.asarray(t, dtype=float)
    ripple = 8.0 * np.sum(np.sin(2 * np.pi * freqs[:, None] * t[None, :] + phases[:, None]), axis=0) / 3.0
    return np.interp(t, pattern_t, pattern_T) + ripple


def road(w, p):
    return p["a"] * np.tanh(w / SMOOTHING_SPEED) + p["b"] * w + p["c_air"] * w * np.abs(w)


def derivative(x, tm, p):
    th1, th2, w1, w2 = x
    shaft = p["k"] * (th1 - th2) + p["c"] * (w1 - w2)
    return np.array([w1, w2, (tm - shaft) / p["J1"], (shaft - road(w2, p)) / p["J2"]])


def simulate(p, tm_samples):
    t, rows = march(lambda x, u: derivative(x, u, p), np.zeros(4), tm_samples, FS, SUBSTEPS,
                    lambda x: (x[3], p["k"] * (x[0] - x[1]) + p["c"] * (x[2] - x[3])))
    return t, rows[:, 0], rows[:, 1]


def write(path, t, tm, w2, shaft):
    write_csv(path, ["t", "T_motor", "w2", "T_shaft"], [t, tm, w2, shaft])


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "road_load")
    os.makedirs(out, exist_ok=True)
    tm_samples = motor_torque(np.arange(int(round(DURATION * FS)) + 1) / FS)
    t, w2, shaft = simulate(TRUTH, tm_samples)
    write(os.path.join(out, "road_load_clean.csv"), t, tm_samples, w2, shaft)
    rng = np.random.default_rng(SEED)
    write(os.path.join(out, "road_load.csv"), t, tm_samples, w2 + rng.normal(0, NOISE["w2"], t.size),
          shaft + rng.normal(0, NOISE["T_shaft"], t.size))
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "constants": {"smoothing_speed": SMOOTHING_SPEED}, "noise_std": NOISE,
                   "fs_hz": FS, "substeps": SUBSTEPS, "seed": SEED,
                   "generator": "scripts/generate_road_load_data.py"}, f, indent=1)
    print(f"wrote {out}: {t.size} samples; vehicle speed {w2.min():.2f} ... {w2.max():.2f} rad/s")
