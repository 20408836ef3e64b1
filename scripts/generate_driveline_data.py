#!/usr/bin/env python3
"""A vehicle driveline with a two-stage clutch damper and its dry-friction hysteresis, a rigid
lossy gearbox and a half-shaft, made independently of tvid: its own equations written out here
and its own fixed-step RK4 (40 substeps a sample, 25 us), numpy only. The hysteresis sticking is
stiff: its slope c_d + Fh/0.01 on the reduced inertia of engine and gearbox input is a real mode
near -56 000 1/s, and RK4 is stable for h*56 000 below 2.785. At 50 us (2.81) the march is on
that limit and off the converged solution by 2e-5 of the shaft torque's magnitude; at 25 us (1.4),
by 2e-8 (against 12.5 us).

An engine (Je, a constant), driven by a measured torque, turns the gearbox input (Jg) through a
clutch damper: a soft first spring stage k1 and a stiff second one k2 beyond the twist theta1 on
either side (tvid's `multistage_spring`, stages [{angle: 0, k: k1}, {angle: theta1, k: k2}], its
kinks smoothed over S = 0.002 rad), a viscous damping c_d, and a hysteresis, dry friction Fh on
the relative speed smoothed over 0.01 rad/s (tvid's `friction` with `between` and `coulomb`).
The gearbox is rigid (tvid's `ideal_gear`): ratio n = 3.5 from its input to its output shaft
(Jo), efficiency eta = 0.93 on the torque it transmits in the direction the power flows. A
half-shaft (ks, ds) turns the vehicle's inertia at the wheels (Jv) against the road load
a*tanh(w/0.1) + c_air*w*|w| (tvid's `road_load`).

    phi(x) = S ln(1 + exp(x / S))   (a softplus, computed stably)
    th = th_e - th_g,   dw = w_e - w_g
    Td = k1 th + (k2 - k1) (phi(th - theta1) - phi(-th - theta1)) + c_d dw + Fh tanh(dw / 0.01)
    Ts = ks (th_g / n - th_v) + ds (w_g / n - w_v)
    Je w_e' = T_engine - Td
    Jv w_v' = Ts - a tanh(w_v / 0.1) - c_air w_v |w_v|

The gearbox ties its input and output (w_g = n w_o), so its torque tau (taken from the input)
follows from the two shafts' equations

    Jg w_g' = Td - tau,   Jo w_o' = -Ts + n f tau,   w_g' = n w_o'
    => w_o' = (n f Td - Ts) / (Jo + n^2 f Jg),   tau = Td - n Jg w_o'

with f = eta ** tanh(P / 1 W), P = tau w_g the power the input gives the gearbox; f depends on
tau, so the two are solved together here by fixed-point iteration (to 1e-14).

Two recordings of 12 s at 1 kHz, each from rest, with different engine-torque programmes (a
launch, a tip-out into overrun, driving again, each with its own levels, timings and multi-sine
of 2-40 Hz): the damper's twist passes theta1 on both sides and its hysteresis sticks and slips.
The recorded outputs are the engine speed, the wheel speed and the half-shaft torque.
Written: driveline_a.csv and driveline_b.csv (noise on the three outputs), driveline_a_clean.csv
and driveline_b_clean.csv (no noise), truth.json with the parameters.

    /usr/bin/python3 scripts/generate_driveline_data.py [OUT_DIR]      (default data/driveline)
"""
import json
import math
import os
import sys

import numpy as np

from recording_rk4 import march, write_csv

TRUTH = {"k1": 500.0, "k2": 2000.0, "c_d": 1.5, "Fh": 8.0, "ks": 12000.0, "ds": 20.0, "a": 50.0,
         "c_air": 0.012, "Jv": 100.0}
CONSTANTS = {"Je": 0.2, "Jg": 0.015, "Jo": 0.005, "ratio": 3.5, "eta": 0.93, "theta1": 0.06,
             "smoothing_angle": 0.002, "hysteresis_smoothing_speed": 0.01, "smoothing_power": 1.0,
             "road_smoothing_speed": 0.1}
FS = 1000.0             # samples per second
DURATION = 12.0         # s, each recording
SUBSTEPS = 40
NOISE = {"w_engine": 0.3, "w_wheel": 0.05, "T_shaft": 15.0}   # rad/s, rad/s, N m
SEEDS = {"a": 20261201, "b": 20261202}

# Each recording's programme: (start [s], level [N m], ramp [s]) steps, each a linear ramp from
# the level before (the launch a slow one, so that the damper's wind-up does not turn the engine
# backwards), and the seed of its multi-sine's phases.
PROGRAMMES = {
    "a": {"levels": [(0.0, 200.0, 0.5), (3.0, -60.0, 0.1), (5.5, 120.0, 0.1), (8.0, -40.0, 0.1), (9.5, 170.0, 0.1)],
          "phase_seed": 31},
    "b": {"levels": [(0.0, 160.0, 0.5), (2.2, 40.0, 0.2), (3.6, -70.0, 0.1), (6.0, 230.0, 0.15), (8.3, -50.0, 0.1),
                     (10.2, 90.0, 0.3)], "phase_seed": 37},
}
RIPPLE_FREQS = np.array([2.0, 3.0, 4.5, 6.5, 8.0, 10.0, 12.5, 15.0, 19.0, 24.0, 30.0, 35.0, 40.0])
RIPPLE = 25.0           # N m, the multi-sine's RMS times sqrt(2)


def engine_torque(t, programme):
    """The programme's levels (each change a linear ramp) and a multi-sine of 2-40 Hz, faded in over
    the launch's ramp so that the engine does not turn backwards from rest."""
    t = np.asarray(t, dtype=float)
    levels = programme["levels"]
    base = np.zeros_like(t)
    for k, (start, level, ramp) in enumerate(levels):
        previous = levels[k - 1][1] if k > 0 else 0.0
        base += (level - previous) * np.clip((t - start) / ramp, 0.0, 1.0)
    phases = np.random.default_rng(programme["phase_seed"]).uniform(0, 2 * np.pi, RIPPLE_FREQS.size)
    ripple = RIPPLE * np.sum(np.sin(2 * np.pi * RIPPLE_FREQS[:, None] * t[None, :] + phases[:, None]), axis=0) \
        / np.sqrt(RIPPLE_FREQS.size)
    return base + np.clip(t / levels[0][2], 0.0, 1.0) * ripple


def softplus(x):
    s = CONSTANTS["smoothing_angle"]
    z = x / s
    return s * (max(z, 0.0) + math.log1p(math.exp(-abs(z))))


def torques(x, p):
    """The clutch damper's torque (engine to gearbox input) and the half-shaft's (output to wheel)."""
    n, theta1 = CONSTANTS["ratio"], CONSTANTS["theta1"]
    th_e, th_g, th_v, w_e, w_g, w_v = x
    th, dw = th_e - th_g, w_e - w_g
    td = (p["k1"] * th + (p["k2"] - p["k1"]) * (softplus(th - theta1) - softplus(-th - theta1)) + p["c_d"] * dw
          + p["Fh"] * math.tanh(dw / CONSTANTS["hysteresis_smoothing_speed"]))
    ts = p["ks"] * (th_g / n - th_v) + p["ds"] * (w_g / n - w_v)
    return td, ts


def gearbox(td, ts, w_g):
    """The output shaft's acceleration and the gearbox torque, f solved with tau."""
    n, jg, jo = CONSTANTS["ratio"], CONSTANTS["Jg"], CONSTANTS["Jo"]
    eta, ps = CONSTANTS["eta"], CONSTANTS["smoothing_power"]
    f = 1.0
    for _ in range(100):
        wo_dot = (n * f * td - ts) / (jo + n * n * f * jg)
        tau = td - n * jg * wo_dot
        f_new = eta ** math.tanh(tau * w_g / ps)
        if abs(f_new - f) < 1e-14:
            f = f_new
            break
        f = f_new
    wo_dot = (n * f * td - ts) / (jo + n * n * f * jg)
    return wo_dot, td - n * jg * wo_dot


def derivative(x, te, p):
    n = CONSTANTS["ratio"]
    x = x.tolist()
    td, ts = torques(x, p)
    wo_dot, _ = gearbox(td, ts, x[4])
    w_v = x[5]
    road = p["a"] * math.tanh(w_v / CONSTANTS["road_smoothing_speed"]) + p["c_air"] * w_v * abs(w_v)
    return np.array([x[3], x[4], w_v, (te - td) / CONSTANTS["Je"], n * wo_dot, (ts - road) / p["Jv"]])


def simulate(p, te_samples):
    """The recorded outputs and, for the facts printed, the twist, relative speed and gear power."""
    def record(x):
        x = x.tolist()
        td, ts = torques(x, p)
        _, tau = gearbox(td, ts, x[4])
        return (x[3], x[5], ts, x[0] - x[1], x[3] - x[4], tau * x[4])
    t, rows = march(lambda x, u: derivative(x, u, p), np.zeros(6), te_samples, FS, SUBSTEPS, record)
    return t, rows


def write(path, t, te, w_e, w_v, t_s):
    write_csv(path, ["t", "T_engine", "w_engine", "w_wheel", "T_shaft"], [t, te, w_e, w_v, t_s])


def zero_crossings(v):
    """Sign changes of v, ignoring exact zeros."""
    s = np.sign(v)
    s = s[s != 0]
    return int(np.count_nonzero(s[1:] != s[:-1]))


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "driveline")
    os.makedirs(out, exist_ok=True)
    theta1, vs = CONSTANTS["theta1"], CONSTANTS["hysteresis_smoothing_speed"]
    for name, programme in PROGRAMMES.items():
        te = engine_torque(np.arange(int(round(DURATION * FS)) + 1) / FS, programme)
        t, rows = simulate(TRUTH, te)
        w_e, w_v, t_s, twist, dw, power = rows.T
        write(os.path.join(out, f"driveline_{name}_clean.csv"), t, te, w_e, w_v, t_s)
        rng = np.random.default_rng(SEEDS[name])
        write(os.path.join(out, f"driveline_{name}.csv"), t, te, w_e + rng.normal(0, NOISE["w_engine"], t.size),
              w_v + rng.normal(0, NOISE["w_wheel"], t.size), t_s + rng.normal(0, NOISE["T_shaft"], t.size))
        print(f"driveline_{name}: {t.size} samples; engine torque {te.min():.0f} ... {te.max():.0f} N m, "
              f"engine {w_e.min():.1f} ... {w_e.max():.1f} rad/s, wheel {w_v.min():.2f} ... {w_v.max():.2f} rad/s, "
              f"shaft torque {t_s.min():.0f} ... {t_s.max():.0f} N m; damper twist {twist.min():.4f} ... "
              f"{twist.max():.4f} rad, {100 * np.mean(twist > theta1):.0f} % beyond +theta1 and "
              f"{100 * np.mean(twist < -theta1):.0f} % beyond -theta1; the hysteresis's relative speed crosses zero "
              f"{zero_crossings(dw)} times, within +-{vs:g} rad/s (sticking) {100 * np.mean(np.abs(dw) < vs):.0f} % "
              f"of the time; power through the gearbox {power.min():.0f} ... {power.max():.0f} W, "
              f"{100 * np.mean(power < 0):.0f} % of the time flowing back")
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "constants": CONSTANTS, "noise_std": NOISE, "fs_hz": FS,
                   "substeps": SUBSTEPS, "seeds": SEEDS, "generator": "scripts/generate_driveline_data.py"}, f, indent=1)
    print(f"wrote {out}")
