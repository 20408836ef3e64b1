#!/usr/bin/env python3
"""A recording of a two-inertia line under a constant load, made independently of tvid: its
own equations written out here and its own fixed-step RK4 (10 substeps a sample), numpy only.

A motor (J1) drives a load (J2) through a shaft (k, c); the load turns against bearing
friction (c2) and a constant braking torque T_load, as a dynamometer holds it. The motor
torque is a measured multi-sine around a mean; the recorded outputs are the load's speed and
the shaft torque. Written: constant_load_clean.csv (no noise) and constant_load.csv (noise
on the two outputs), truth.json with the parameters.

    /usr/bin/python3 scripts/generate_constant_load_data.py [OUT_DIR]      (default data/constant_load)
"""
import json
import os
import sys

import numpy as np

TRUTH = {"J1": 0.05, "J2": 0.20, "k": 800.0, "c": 1.5, "c2": 0.08, "T_load": -12.0}
FS = 1000.0          # samples per second
DURATION = 4.0       # s
SUBSTEPS = 10
NOISE = {"w2": 0.05, "T_shaft": 0.2}   # rad/s, N m
SEED = 20261127


def motor_torque(t):
    """A mean of 20 N m with a multi-sine of 2-40 Hz on it."""
    rng = np.random.default_rng(7)
    freqs = np.array([2.0, 3.5, 5.0, 7.5, 11.0, 16.0, 23.0, 31.0, 40.0])
    phases = rng.uniform(0, 2 * np.pi, freqs.size)
    t = np.asarray(t, dtype=float)
    return 20.0 + 6.0 * np.sum(np.sin(2 * np.pi * freqs[:, None] * t[None, :] + phases[:, None]), axis=0) / 3.0


def derivative(x, tm, p):
    th1, th2, w1, w2 = x
    shaft = p["k"] * (th1 - th2) + p["c"] * (w1 - w2)
    dw1 = (tm - shaft) / p["J1"]
    dw2 = (shaft - p["c2"] * w2 + p["T_load"]) / p["J2"]
    return np.array([w1, w2, dw1, dw2])


def simulate(p):
    n = int(round(DURATION * FS)) + 1
    t = np.arange(n) / FS
    h = 1.0 / FS / SUBSTEPS
    x = np.zeros(4)  # at rest
    w2 = np.empty(n)
    shaft = np.empty(n)
    for i in range(n):
        w2[i] = x[3]
        shaft[i] = p["k"] * (x[0] - x[1]) + p["c"] * (x[2] - x[3])
        if i == n - 1:
            break
        for s in range(SUBSTEPS):
            ts = t[i] + s * h
            # The motor torque between samples: linear interpolation of the samples, as a
            # recorded channel is read.
            u = lambda tau: np.interp(tau, [t[i], t[i + 1]], [tm_samples[i], tm_samples[i + 1]])
            k1 = derivative(x, u(ts), p)
            k2 = derivative(x + 0.5 * h * k1, u(ts + 0.5 * h), p)
            k3 = derivative(x + 0.5 * h * k2, u(ts + 0.5 * h), p)
            k4 = derivative(x + h * k3, u(ts + h), p)
            x = x + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    return t, w2, shaft


def write(path, t, tm, w2, shaft):
    with open(path, "w") as f:
        f.write("t,T_motor,w2,T_shaft\n")
        for row in zip(t, tm, w2, shaft):
            f.write(",".join(f"{v:.12g}" for v in row) + "\n")


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "constant_load")
    os.makedirs(out, exist_ok=True)
    t_all = np.arange(int(round(DURATION * FS)) + 1) / FS
    tm_samples = motor_torque(t_all)
    t, w2, shaft = simulate(TRUTH)
    write(os.path.join(out, "constant_load_clean.csv"), t, tm_samples, w2, shaft)
    rng = np.random.default_rng(SEED)
    write(os.path.join(out, "constant_load.csv"), t, tm_samples, w2 + rng.normal(0, NOISE["w2"], t.size),
          shaft + rng.normal(0, NOISE["T_shaft"], t.size))
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "noise_std": NOISE, "fs_hz": FS, "substeps": SUBSTEPS, "seed": SEED,
                   "generator": "scripts/generate_constant_load_data.py"}, f, indent=1)
    print(f"wrote {out}: {t.size} samples; mean load speed {w2[-1000:].mean():.3f} rad/s")
