#!/usr/bin/env python3
"""A vehicle launch through a rigid lossy gearbox, made independently of tvid: its own
equations written out here and its own fixed-step RK4 (10 substeps a sample), numpy only.

An engine (Je), driven by a measured torque, turns the gearbox input (Jg) through a clutch
damper (kc, cc). The gearbox is rigid: ratio n = 3.5 from its input to its output shaft (Jo),
efficiency eta on the torque it transmits in the direction the power flows. A half-shaft
(ks, ds) turns the vehicle's inertia at the wheels (Jv) against the road load
a*tanh(w/0.1) + c_air*w*|w|. The engine launches the vehicle from rest, brakes it (the power
then flows back through the gearbox), drives it again and brakes again, with a multi-sine of
2-40 Hz on its torque throughout.

The gearbox ties its input and output (w_g = n w_o), so its torque tau (taken from the input)
follows from the two shafts' equations

    Jg wg' = Tc - tau,   Jo wo' = -Ts + n f tau,   wg' = n wo'
    => wo' = (n f Tc - Ts) / (Jo + n^2 f Jg),   tau = Tc - n Jg wo'

with f = eta ** tanh(P / 1 W), P = tau wg the power the input gives the gearbox; f depends on
tau, so the two are solved together here by fixed-point iteration (to 1e-14).

The recorded outputs are the engine speed, the wheel speed and the half-shaft torque.
Written: rigid_gear_clean.csv (no noise) and rigid_gear.csv (noise on the three outputs, and
a column T_engine_logged: the engine torque as a logger records it, with white noise of
1.5 N m that the vehicle never felt), truth.json with the parameters.

    /usr/bin/python3 scripts/generate_rigid_gear_data.py [OUT_DIR]      (default data/rigid_gear)
"""
import json
import os
import sys

import numpy as np

from recording_rk4 import march, write_csv

TRUTH = {"Je": 0.2, "kc": 600.0, "cc": 2.0, "ks": 6000.0, "ds": 15.0, "Jv": 1.2, "a": 15.0,
         "c_air": 0.01, "eta": 0.93}
CONSTANTS = {"Jg": 0.02, "Jo": 0.005, "ratio": 3.5, "smoothing_power": 1.0, "smoothing_speed": 0.1}
FS = 1000.0             # samples per second
DURATION = 6.0          # s
SUBSTEPS = 10
NOISE = {"w_engine": 0.3, "w_wheel": 0.05, "T_shaft": 2.0}   # rad/s, rad/s, N m
INPUT_NOISE = {"T_engine_logged": 1.5}                        # N m, on the logged engine torque
SEED = 20261129


def engine_torque(t):
    """Launch at 60 N m, engine braking at -40 N m, drive at 40 N m, brake at -30 N m (each
    change a 0.1 s ramp), and a multi-sine of 2-40 Hz of about 4 N m that rings both shafts."""
    t = np.asarray(t, dtype=float)
    levels = [(0.0, 60.0), (1.5, -40.0), (2.2, 40.0), (4.0, -30.0)]
    base = np.zeros_like(t)
    for k, (start, level) in enumerate(levels):
        previous = levels[k - 1][1] if k > 0 else 0.0
        base += (level - previous) * np.clip((t - start) / 0.1, 0.0, 1.0)
    rng = np.random.default_rng(29)
    freqs = np.array([2.0, 3.5, 6.0, 9.5, 14.0, 19.0, 24.0, 28.0, 33.0, 40.0])
    phases = rng.uniform(0, 2 * np.pi, freqs.size)
    ripple = 4.0 * np.sum(np.sin(2 * np.pi * freqs[:, None] * t[None, :] + phases[:, None]), axis=0) / np.sqrt(freqs.size / 2)
    return base + ripple


def torques(x, p):
    """The clutch torque (engine to gearbox input) and the half-shaft torque (output to wheel)."""
    n = CONSTANTS["ratio"]
    th_e, th_g, th_v, w_e, w_g, w_v = x
    tc = p["kc"] * (th_e - th_g) + p["cc"] * (w_e - w_g)
    ts = p["ks"] * (th_g / n - th_v) + p["ds"] * (w_g / n - w_v)
    return tc, ts


def gearbox(tc, ts, w_g, p):
    """The output shaft's acceleration and the gearbox torque, f solved with tau."""
    n, jg, jo, ps = CONSTANTS["ratio"], CONSTANTS["Jg"], CONSTANTS["Jo"], CONSTANTS["smoothing_power"]
    f = 1.0
    for _ in range(100):
        wo_dot = (n * f * tc - ts) / (jo + n * n * f * jg)
        tau = tc - n * jg * wo_dot
        f_new = p["eta"] ** np.tanh(tau * w_g / ps)
        if abs(f_new - f) < 1e-14:
            break
        f = f_new
    wo_dot = (n * f * tc - ts) / (jo + n * n * f * jg)
    return wo_dot, tc - n * jg * wo_dot


def derivative(x, te, p):
    n = CONSTANTS["ratio"]
    tc, ts = torques(x, p)
    wo_dot, _ = gearbox(tc, ts, x[4], p)
    road = p["a"] * np.tanh(x[5] / CONSTANTS["smoothing_speed"]) + p["c_air"] * x[5] * abs(x[5])
    return np.array([x[3], x[4], x[5], (te - tc) / p["Je"], n * wo_dot, (ts - road) / p["Jv"]])


def simulate(p, te_samples):
    def record(x):
        tc, ts = torques(x, p)
        _, tau = gearbox(tc, ts, x[4], p)
        return (x[3], x[5], ts, tau * x[4])
    t, rows = march(lambda x, u: derivative(x, u, p), np.zeros(6), te_samples, FS, SUBSTEPS, record)
    return t, rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3]


def write(path, t, te, w_e, w_v, t_s, logged=()):
    names = ["t", "T_engine", "w_engine", "w_wheel", "T_shaft"] + (["T_engine_logged"] if len(logged) else [])
    write_csv(path, names, [t, te, w_e, w_v, t_s] + ([logged] if len(logged) else []))


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "rigid_gear")
    os.makedirs(out, exist_ok=True)
    te = engine_torque(np.arange(int(round(DURATION * FS)) + 1) / FS)
    t, w_e, w_v, t_s, power = simulate(TRUTH, te)
    write(os.path.join(out, "rigid_gear_clean.csv"), t, te, w_e, w_v, t_s)
    rng = np.random.default_rng(SEED)
    noisy = (w_e + rng.normal(0, NOISE["w_engine"], t.size), w_v + rng.normal(0, NOISE["w_wheel"], t.size),
             t_s + rng.normal(0, NOISE["T_shaft"], t.size))
    logged = te + np.random.default_rng(SEED + 1).normal(0, INPUT_NOISE["T_engine_logged"], t.size)
    write(os.path.join(out, "rigid_gear.csv"), t, te, *noisy, logged)
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "constants": CONSTANTS, "noise_std": NOISE, "input_noise_std": INPUT_NOISE, "fs_hz": FS,
                   "substeps": SUBSTEPS, "seed": SEED, "generator": "scripts/generate_rigid_gear_data.py"}, f, indent=1)
    print(f"wrote {out}: {t.size} samples; wheel speed {w_v.min():.2f} ... {w_v.max():.2f} rad/s, "
          f"engine {w_e.min():.1f} ... {w_e.max():.1f} rad/s, shaft torque {t_s.min():.0f} ... {t_s.max():.0f} N m, "
          f"power through the gearbox {power.min():.0f} ... {power.max():.0f} W, "
          f"{100 * np.mean(power < 0):.0f} % of the time flowing back")
