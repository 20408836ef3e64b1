#!/usr/bin/env python3
"""A recording of an engine driving a gearbox through a two-stage clutch damper, made
independently of tvid: its own equations written out here and its own fixed-step RK4 (10
substeps a sample), numpy only.

The engine (J1) is driven by a measured torque: a mean, a slow swing between drive and
overrun, and the firing pulsation. The clutch damper between engine and gearbox (J2) has a
soft first stage and a stiff second one beyond the twist theta1 on either side (tvid's
`multistage_spring` with stages [{angle: 0, k: k1}, {angle: theta1, k: k2}]), a viscous
damping c, and a hysteresis, dry friction Fh on the relative speed (tvid's `friction` with
coulomb Fh between the two). The gearbox turns against viscous friction c2 to ground:

    phi(x) = S ln(1 + exp(x / S)),   S = 0.002 rad (a softplus, computed stably)
    th = th1 - th2,  T_spring = k1 th + (k2 - k1) (phi(th - theta1) - phi(-th - theta1)) + c (w1 - w2)
    T_hyst = Fh tanh((w1 - w2) / 0.05)
    J1 w1' = T_e - T_spring - T_hyst,   J2 w2' = T_spring + T_hyst - c2 w2

The recorded outputs are the two speeds. Written: clutch_damper_clean.csv (no noise) and
clutch_damper.csv (noise on w1 and w2), truth.json with the parameters.

    /usr/bin/python3 scripts/generate_clutch_damper_data.py [OUT_DIR]      (default data/clutch_damper)
"""
import json
import os
import sys

import numpy as np

from recording_rk4 import march, write_csv

TRUTH = {"J1": 0.2, "J2": 0.5, "k1": 300.0, "k2": 3000.0, "theta1": 0.03, "c": 2.0, "Fh": 3.0, "c2": 0.3}
SMOOTHING_ANGLE = 0.002   # rad, a constant of the model
SMOOTHING_SPEED = 0.05    # rad/s, of the hysteresis
FS = 1000.0               # samples per second
DURATION = 5.0            # s
SUBSTEPS = 10
NOISE = {"w1": 0.05, "w2": 0.05}   # rad/s
SEED = 20261131


def engine_torque(t):
    """A mean of 10 N m, a swing of +-40 N m at 0.7 Hz and a firing pulsation of 30 N m whose
    frequency rises from 12 to 36 Hz, as in a run-up, through the damper's resonances."""
    t = np.asarray(t, dtype=float)
    return 10.0 + 40.0 * np.sin(2 * np.pi * 0.7 * t) + 30.0 * np.sin(2 * np.pi * (12.0 * t + 2.4 * t ** 2))


def softplus(x):
    z = x / SMOOTHING_ANGLE
    return SMOOTHING_ANGLE * (np.maximum(z, 0.0) + np.log1p(np.exp(-np.abs(z))))


def damper(th, thd, p):
    """The torque of the clutch damper's springs, damping and hysteresis."""
    spring = p["k1"] * th + (p["k2"] - p["k1"]) * (softplus(th - p["theta1"]) - softplus(-th - p["theta1"]))
    return spring + p["c"] * thd + p["Fh"] * np.tanh(thd / SMOOTHING_SPEED)


def derivative(x, te, p):
    th1, th2, w1, w2 = x
    t_d = damper(th1 - th2, w1 - w2, p)
    return np.array([w1, w2, (te - t_d) / p["J1"], (t_d - p["c2"] * w2) / p["J2"]])


def simulate(p, te_samples):
    t, rows = march(lambda x, u: derivative(x, u, p), np.zeros(4), te_samples, FS, SUBSTEPS,
                    lambda x: (x[2], x[3], x[0] - x[1]))  # w1, w2, twist
    return t, rows[:, 0], rows[:, 1], rows[:, 2]


def write(path, t, te, w1, w2):
    write_csv(path, ["t", "T_engine", "w1", "w2"], [t, te, w1, w2])


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "clutch_damper")
    os.makedirs(out, exist_ok=True)
    te_samples = engine_torque(np.arange(int(round(DURATION * FS)) + 1) / FS)
    t, w1, w2, twist = simulate(TRUTH, te_samples)
    write(os.path.join(out, "clutch_damper_clean.csv"), t, te_samples, w1, w2)
    rng = np.random.default_rng(SEED)
    write(os.path.join(out, "clutch_damper.csv"), t, te_samples, w1 + rng.normal(0, NOISE["w1"], t.size),
          w2 + rng.normal(0, NOISE["w2"], t.size))
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "constants": {"smoothing_angle": SMOOTHING_ANGLE,
                                                      "hysteresis_smoothing_speed": SMOOTHING_SPEED},
                   "noise_std": NOISE, "fs_hz": FS, "substeps": SUBSTEPS, "seed": SEED,
                   "generator": "scripts/generate_clutch_damper_data.py"}, f, indent=1)
    beyond = np.abs(twist) > TRUTH["theta1"]
    print(f"wrote {out}: {t.size} samples; twist {twist.min():.4f} ... {twist.max():.4f} rad, "
          f"{100 * beyond.mean():.0f} % of the time in the second stage")
