#!/usr/bin/env python3
"""A recording of a positioning drive under a PD position controller, made independently of
tvid: its own equations written out here and its own fixed-step RK4 (10 substeps a sample),
numpy only.

A motor and ball screw (one inertia J) turn against viscous (c) and Coulomb (Fc) friction,
the sign smoothed as tvid's friction element smooths it: tanh(w / 0.05). A position
controller drives it to a recorded angle setpoint with derivative action on the measured
speed: T = kp (theta_ref - theta) - kd w. The setpoint is a series of point-to-point moves
(cycloidal profiles, back and forth, of different lengths and durations). Recorded: the
motor angle (the encoder) and the controller's torque (the drive's current times its torque
constant). Written: positioning_drive_clean.csv (no noise), positioning_drive.csv (noise on
both outputs), truth.json.

    /usr/bin/python3 scripts/generate_positioning_drive_data.py [OUT_DIR]   (default data/positioning_drive)
"""
import json
import os
import sys

import numpy as np

TRUTH = {"J": 0.002, "c": 0.01, "Fc": 0.15, "kp": 20.0, "kd": 0.4}
SMOOTHING_SPEED = 0.05   # rad/s
FS = 1000.0              # samples per second
DURATION = 4.0           # s
SUBSTEPS = 10
NOISE = {"theta": 2e-4, "T_servo": 0.02}   # rad, N m
SEED = 20261130

# (start time, duration, distance [rad]) of each move; the setpoint rests between them.
MOVES = [(0.2, 0.30, 2.0), (0.8, 0.15, -1.2), (1.3, 0.40, -3.0), (2.0, 0.10, 0.5),
         (2.4, 0.25, 2.5), (3.0, 0.20, -0.8), (3.5, 0.30, 1.5)]


def setpoint(t):
    """Cycloidal moves: theta = d (s - sin(2 pi s) / (2 pi)), s the move's fraction done."""
    t = np.asarray(t, dtype=float)
    theta = np.zeros_like(t)
    for start, length, distance in MOVES:
        s = np.clip((t - start) / length, 0.0, 1.0)
        theta += distance * (s - np.sin(2 * np.pi * s) / (2 * np.pi))
    return theta


def controller(theta, w, ref, p):
    return p["kp"] * (ref - theta) - p["kd"] * w


def friction(w, p):
    return p["c"] * w + p["Fc"] * np.tanh(w / SMOOTHING_SPEED)


def simulate(p, t, ref):
    h = 1.0 / FS / SUBSTEPS
    theta, w = 0.0, 0.0  # at rest at the setpoint's start
    out_theta = np.empty(t.size)
    out_torque = np.empty(t.size)

    def f(th, om, r):
        return om, (controller(th, om, r, p) - friction(om, p)) / p["J"]

    for i in range(t.size):
        out_theta[i] = theta
        out_torque[i] = controller(theta, w, ref[i], p)
        if i == t.size - 1:
            break
        for s in range(SUBSTEPS):
            # The setpoint between samples: linear interpolation of the samples, as a channel is read.
            r0 = ref[i] + (ref[i + 1] - ref[i]) * s / SUBSTEPS
            rm = ref[i] + (ref[i + 1] - ref[i]) * (s + 0.5) / SUBSTEPS
            r1 = ref[i] + (ref[i + 1] - ref[i]) * (s + 1) / SUBSTEPS
            k1 = f(theta, w, r0)
            k2 = f(theta + 0.5 * h * k1[0], w + 0.5 * h * k1[1], rm)
            k3 = f(theta + 0.5 * h * k2[0], w + 0.5 * h * k2[1], rm)
            k4 = f(theta + h * k3[0], w + h * k3[1], r1)
            theta += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            w += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    return out_theta, out_torque


def write(path, t, ref, theta, torque):
    with open(path, "w") as f:
        f.write("t,theta_ref,theta,T_servo\n")
        for row in zip(t, ref, theta, torque):
            f.write(",".join(f"{v:.12g}" for v in row) + "\n")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "positioning_drive")
    os.makedirs(out, exist_ok=True)
    t = np.arange(int(round(DURATION * FS)) + 1) / FS
    ref = setpoint(t)
    theta, torque = simulate(TRUTH, t, ref)
    write(os.path.join(out, "positioning_drive_clean.csv"), t, ref, theta, torque)
    rng = np.random.default_rng(SEED)
    write(os.path.join(out, "positioning_drive.csv"), t, ref, theta + rng.normal(0, NOISE["theta"], t.size),
          torque + rng.normal(0, NOISE["T_servo"], t.size))
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "noise_std": NOISE, "fs_hz": FS, "substeps": SUBSTEPS, "seed": SEED,
                   "smoothing_speed": SMOOTHING_SPEED, "generator": "scripts/generate_positioning_drive_data.py"},
                  f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
