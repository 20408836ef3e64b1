#!/usr/bin/env python3
"""A recording of a positioning drive under a digital position controller, made independently
of tvid: its own equations written out here and its own fixed-step RK4 (10 substeps a sample),
numpy only.

A motor and ball screw (one inertia J) turn against viscous (c) and Coulomb (Fc) friction,
the sign smoothed as tvid's friction element smooths it: tanh(w / 0.05). The drive's firmware
runs its position loop at 1 kHz:
  - at every sample instant t_k = k Ts it reads the encoder angle theta_k and the setpoint;
  - its speed is the backward difference of the averages of the last N = 2 angles,
    (theta_k - theta_{k-N}) / (N Ts);
  - its integral adds ki Ts (ref_k - theta_k) and is kept within the torque limits;
  - its command kp (ref_k - theta_k) + integral - kd speed is saturated at the limits and
    applied one sample later (the computation delay), held constant until the next command.
Before the recording the drive stood still at the start, so its memory holds that angle and
its first command. Recorded at 1 kHz: the motor angle (the encoder) and the torque the drive
applies (its current times its torque constant), at each sample the command applied from it on.
Written: digital_drive_clean.csv (no noise), digital_drive.csv (noise on both outputs),
truth.json.

    /usr/bin/python3 scripts/generate_digital_drive_data.py [OUT_DIR]   (default data/digital_drive)
"""
import json
import os
import sys

import numpy as np

from recording_rk4 import write_csv

TRUTH = {"J": 0.002, "c": 0.01, "Fc": 0.15, "kp": 20.0, "ki": 60.0, "kd": 0.4}
LIMITS = (-0.9, 0.9)     # N m
SAMPLE_PERIOD = 0.001    # s: the controller's clock
DELAY_SAMPLES = 1        # the computation delay
ANGLE_AVERAGE = 2        # angles averaged before the speed's backward difference
SMOOTHING_SPEED = 0.05   # rad/s
FS = 1000.0              # samples per second
DURATION = 4.0           # s
SUBSTEPS = 10
NOISE = {"theta": 2e-4, "T_drive": 0.02}   # rad, N m
SEED = 20261127

# (start time, duration, distance [rad]) of each move; the setpoint rests between them.
# The 0.1 s move of 0.9 rad asks for more than the drive's limit: it saturates.
MOVES = [(0.2, 0.30, 2.0), (0.8, 0.15, -1.2), (1.3, 0.40, -3.0), (2.0, 0.10, 0.9),
         (2.4, 0.25, 2.5), (3.0, 0.20, -0.8), (3.5, 0.30, 1.5)]


def setpoint(t):
    """Cycloidal moves: theta = d (s - sin(2 pi s) / (2 pi)), s the move's fraction done."""
    t = np.asarray(t, dtype=float)
    theta = np.zeros_like(t)
    for start, length, distance in MOVES:
        s = np.clip((t - start) / length, 0.0, 1.0)
        theta += distance * (s - np.sin(2 * np.pi * s) / (2 * np.pi))
    return theta


def friction(w, p):
    return p["c"] * w + p["Fc"] * np.tanh(w / SMOOTHING_SPEED)


class Firmware:
    """The drive's position loop, sampled: its memory of angles and commands."""

    def __init__(self, p, theta0, ref0):
        self.p = p
        self.angles = [theta0] * (ANGLE_AVERAGE + 1)   # standing still: every past angle the same
        self.integral = 0.0
        first = self.saturate(p["kp"] * (ref0 - theta0))
        self.commands = [first] * (DELAY_SAMPLES + 1)  # the delay line, newest last

    def saturate(self, v):
        return min(max(v, LIMITS[0]), LIMITS[1])

    def sample(self, theta, ref):
        p = self.p
        self.angles = self.angles[1:] + [theta]
        speed = (self.angles[-1] - self.angles[0]) / (ANGLE_AVERAGE * SAMPLE_PERIOD)
        error = ref - theta
        self.integral = self.saturate(self.integral + p["ki"] * SAMPLE_PERIOD * error)
        command = self.saturate(p["kp"] * error + self.integral - p["kd"] * speed)
        self.commands = self.commands[1:] + [command]
        return self.commands[0]   # the command computed DELAY_SAMPLES samples ago


def simulate(p, t, ref):
    h = 1.0 / FS / SUBSTEPS
    theta, w = 0.0, 0.0  # at rest at the setpoint's start
    firmware = Firmware(p, theta, ref[0])
    held = firmware.commands[0]
    out_theta = np.empty(t.size)
    out_torque = np.empty(t.size)
    every = int(round(SAMPLE_PERIOD * FS))
    for i in range(t.size):
        if i > 0 and i % every == 0:
            held = firmware.sample(theta, ref[i])
        out_theta[i] = theta
        out_torque[i] = held
        if i == t.size - 1:
            break

        def f(th, om):
            return om, (held - friction(om, p)) / p["J"]

        for _ in range(SUBSTEPS):
            k1 = f(theta, w)
            k2 = f(theta + 0.5 * h * k1[0], w + 0.5 * h * k1[1])
            k3 = f(theta + 0.5 * h * k2[0], w + 0.5 * h * k2[1])
            k4 = f(theta + h * k3[0], w + h * k3[1])
            theta += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            w += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    return out_theta, out_torque


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "digital_drive")
    os.makedirs(out, exist_ok=True)
    t = np.arange(int(round(DURATION * FS)) + 1) / FS
    ref = setpoint(t)
    theta, torque = simulate(TRUTH, t, ref)
    header = ["t", "theta_ref", "theta", "T_drive"]
    write_csv(os.path.join(out, "digital_drive_clean.csv"), header, [t, ref, theta, torque])
    rng = np.random.default_rng(SEED)
    write_csv(os.path.join(out, "digital_drive.csv"), header,
              [t, ref, theta + rng.normal(0, NOISE["theta"], t.size), torque + rng.normal(0, NOISE["T_drive"], t.size)])
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"parameters": TRUTH, "limits": LIMITS, "sample_period": SAMPLE_PERIOD,
                   "delay_samples": DELAY_SAMPLES, "angle_average": ANGLE_AVERAGE, "noise_std": NOISE,
                   "fs_hz": FS, "substeps": SUBSTEPS, "seed": SEED, "smoothing_speed": SMOOTHING_SPEED,
                   "generator": "scripts/generate_digital_drive_data.py"}, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
