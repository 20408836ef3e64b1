#!/usr/bin/env python3
"""A recording for the inverse friction model, made independently of tvid, numpy only; no
integrator: the torque follows from the speed.

A cart (a shaft, inertia J) is moved along a smooth speed profile w(t), a sum of sines
that crosses zero many times and briskly. The torque that takes, with viscous friction c
and Coulomb friction Fc with the exact sign, is

    T_m = J dw/dt + c w + Fc sign(w)

with dw/dt the profile's exact derivative. This is the set-up of the published inverse
models: the speed is prescribed, the drive's torque is the output, and the friction is
linear in its parameters, once with the measured -sign(w) as a regressor (a torque input)
and once as a smoothed friction law. Columns t, w, T_m and minus_sign_w = -sign(w).
Written: inverse_friction_clean.csv (no noise) and inverse_friction.csv (noise on T_m
only), truth.json with the parameters.

    /usr/bin/python3 scripts/generate_inverse_friction_data.py [OUT_DIR]      (default data/inverse_friction)
"""
import json
import os
import sys

import numpy as np

TRUTH = {"J": 0.02, "c": 0.1, "Fc": 0.8}
FS = 1000.0          # samples per second
DURATION = 4.0       # s
NOISE = {"T_m": 0.02}   # N m
SEED = 20261129


def speed_profile(t):
    """A sum of sines of 1.5-6.1 Hz, peaks of about 10 rad/s, from rest at t = 0: the speed and
    its exact derivative. The signs are chosen so that every zero crossing is brisk (above
    50 rad/s^2), and the smoothed sign differs from the exact one on a sample or two."""
    freqs = np.array([1.5, 2.3, 3.7, 4.9, 6.1])
    amps = np.array([4.0, -3.0, -2.5, -2.0, 1.5])
    arg = 2 * np.pi * freqs[:, None] * t[None, :]
    w = np.sum(amps[:, None] * np.sin(arg), axis=0)
    dw = np.sum((2 * np.pi * freqs * amps)[:, None] * np.cos(arg), axis=0)
    return w, dw


def drive_torque(p, w, dw):
    return p["J"] * dw + p["c"] * w + p["Fc"] * np.sign(w)


def write(path, t, w, tm):
    with open(path, "w") as f:
        f.write("t,w,T_m,minus_sign_w\n")
        for row in zip(t, w, tm, 0.0 - np.sign(w)):
            f.write(",".join(f"{v:.12g}" for v in row) + "\n")


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "inverse_friction")
    os.makedirs(out, exist_ok=True)
    t = np.arange(int(round(DURATION * FS)) + 1) / FS
    w, dw = speed_profile(t)
    tm = drive_torque(TRUTH, w, dw)
    write(os.path.join(out, "inverse_friction_clean.csv"), t, w, tm)
    rng = np.random.default_rng(SEED)
    write(os.path.join(out, "inverse_friction.csv"), t, w, tm + rng.normal(0, NOISE["T_m"], t.size))
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "noise_std": NOISE, "fs_hz": FS, "seed": SEED,
                   "generator": "scripts/generate_inverse_friction_data.py"}, f, indent=1)
    crossings = np.sum(np.diff(np.sign(w)) != 0)
    print(f"wrote {out}: {t.size} samples; speed {w.min():.2f} ... {w.max():.2f} rad/s, {crossings} zero crossings, "
          f"slowest at {np.abs(dw[:-1][np.diff(np.sign(w)) != 0]).min():.1f} rad/s^2")
