#!/usr/bin/env python3
"""Generate the synthetic engine-block idle reference data set in data/engine/.

What it generates
-----------------
A deterministic, synthetic stand-in for the idle recording of the methodology paper
("Methodology for Modeling, Parameter Estimation, and Validation of Powertrain
Torsional Vibration"): the four in-cylinder pressures and the damping-wheel and
flywheel speeds of a four-cylinder engine idling with the clutch disengaged at
about 130 rad/s, sampled every 0.5 deg of flywheel (crank) angle.

The model is the engine_block preset of tvid (the methodology paper eqs. 1-4):

* nodes: 0 = damping wheel (J1), 1..4 = crank throws of cylinders 1..4 in their
  physical order along the crank (J2 each), 5 = flywheel (J3);
* spring-dampers wheel-throw1 (K21, C21), throw i - throw i+1 (Kxx, Cxx),
  throw4-flywheel (K32, C32): torque on a = -K (theta_a - theta_b) - C (w_a - w_b),
  the opposite on b;
* friction to ground -C1 w (wheel), -C2 w (each throw), -C3 w (flywheel);
* a cylinder on each throw, firing order 1-3-4-2: cylinder c at firing position
  k_c (cyl1 0, cyl3 1, cyl4 2, cyl2 3) has its firing TDC at crank angle
  k_c*180 deg; local crank angle phi_c = theta_c - k_c*pi;
      s'(phi)  = r sin(phi) + r^2 sin(2 phi) / (2 sqrt(l^2 - r^2 sin^2 phi))
      s''(phi) = r cos(phi) + r^2 cos(2 phi) / sqrt(l^2 - r^2 sin^2 phi)
                 + r^4 sin^2(2 phi) / (4 (l^2 - r^2 sin^2 phi)^(3/2))
      (J2 + m s'^2) theta_c'' = (spring, damper and friction torques on the throw)
                                + (p_c - p_atm) (pi B^2/4) s' - m s' s'' w_c^2
  (the exact reciprocating-mass torque -m s' (s' theta'' + s'' w^2), with the
  theta'' part moved to the left side). The seed's eq. 4 prints sin^2(2 theta)
  under the root; that is a typo, the piston kinematics use sin^2(phi).
* p_c is looked up by the throw's OWN angle theta_c in the tabulated pressure trace
  of cylinder c over the crank-angle grid alpha_j = j * 0.5 deg, by linear
  interpolation. The table is exactly the pressure column of the clean CSV
  (after rounding to %.10g bar).

Pressure model: single-zone model of Eriksson & Andersson (compression polytrope
from intake valve closing, expansion polytrope from a pressure raised by the heat
released, Wiebe burn fraction p = (1 - x_b) p_c + x_b p_e), blended smoothly with
the intake (0.35 bar) and exhaust (1.05 bar) strokes; cycle-to-cycle variation of
the heat release (4 % std) and the start of combustion (1.5 deg std). The mean
heat release is tuned so that the indicated torque balances the friction
(C1 + 4 C2 + C3) * 130 rad/s.

Simulation: classic fixed-step RK4 (step 2 us; a step in which a throw angle
crosses a 0.5 deg grid angle, where the interpolated pressure has a slope change,
is split there), all nodes start at theta = 0, w = 130 rad/s; 20 warm-up cycles,
then 10 recorded cycles (re-based to crank_deg 0). A sample is taken each
time the flywheel angle crosses alpha_j: the crossing time is located to 1e-12 s
(cubic Hermite inside the step, then Newton on a partial RK4 step from the step
start) and the recorded state is that partial RK4 step. A second run with half the
step checks the convergence (printed; must be < 1e-7 rad/s).

Files written (default folder: <repository root>/data/engine)
------------------------------------------------------------
* idle_clean.csv  noise-free, columns t,crank_deg,p_cyl1..p_cyl4,omega_dw,omega_fw
* idle.csv        the same with Gaussian measurement noise (0.02 bar on each
                  pressure, 0.08 rad/s on each speed; t and crank_deg exact)
* truth.json      constants, true parameters, noise, seeds, statistics,
                  reference residual ratios
* README.md       description of the data set

All numbers are written with '%.10g'. Only the Python 3 standard library is used;
the output is deterministic (the half-step check runs in a second process).

Usage:  python3 scripts/generate_engine_data.py [--out data/engine] [--quiet]
"""

import argparse
import concurrent.futures
import json
import math
import os
import random
import sys
import time

# --------------------------------------------------------------------------------------
# Fixed settings
# --------------------------------------------------------------------------------------

SEED = 20240607            # combustion cycle-to-cycle variation
NOISE_SEED = SEED + 1      # measurement noise
FMT = "%.10g"
SCRIPT_NAME = "scripts/generate_engine_data.py"

# Engine geometry and fixed (not estimated) constants, SI units.
CONSTANTS = {
    "cylinders": 4,
    "firing_order": [1, 3, 4, 2],
    "bore": 0.079,            # m
    "crank_radius": 0.0405,   # m
    "rod_length": 0.129,      # m
    "p_atm": 101300.0,        # Pa
    "K21": 8.0e4,             # N m/rad, damping wheel - throw 1
    "Kxx": 3.0e5,             # N m/rad, between throws
    "K32": 2.0e5,             # N m/rad, throw 4 - flywheel
}

PARAM_NAMES = ["J1", "J2", "J3", "m", "C1", "C2", "C3", "C21", "C32", "Cxx"]
TRUE_PARAMS = {
    "J1": 0.0045,   # kg m^2, damping wheel
    "J2": 0.0012,   # kg m^2, each crank throw
    "J3": 0.12,     # kg m^2, flywheel
    "m": 0.45,      # kg, reciprocating mass per cylinder
    "C1": 0.010,    # N m s/rad, friction of the damping wheel
    "C2": 0.020,    # N m s/rad, friction of each throw
    "C3": 0.025,    # N m s/rad, friction of the flywheel
    "C21": 2.5,     # N m s/rad, damping wheel - throw 1
    "C32": 4.0,     # N m s/rad, throw 4 - flywheel
    "Cxx": 1.5,     # N m s/rad, between throws
}
UNITS = {"J1": "kg m^2", "J2": "kg m^2", "J3": "kg m^2", "m": "kg",
         "C1": "N m s/rad", "C2": "N m s/rad", "C3": "N m s/rad",
         "C21": "N m s/rad", "C32": "N m s/rad", "Cxx": "N m s/rad"}

# Pressure model (per cylinder, local angle theta in deg, 0 = firing TDC).
PRESSURE_MODEL = {
    "compression_ratio": 10.5,
    "p_intake": 0.35e5,        # Pa, manifold pressure at idle (throttled)
    "p_exhaust": 1.05e5,       # Pa
    "theta_ivc": -150.0,       # deg, intake valve closing (30 deg ABDC)
    "kappa_compression": 1.32,
    "kappa_expansion": 1.30,   # also (gamma - 1) of the heat-release pressure rise
    "theta_soc_mean": -8.0,    # deg, start of combustion
    "theta_soc_std": 1.5,      # deg, cycle-to-cycle
    "burn_duration": 50.0,     # deg, Wiebe Delta theta
    "wiebe_a": 5.0,
    "wiebe_m": 2.0,            # x_b = 1 - exp(-a u^(m+1)), u = (theta - soc)/duration
    "heat_release_std": 0.04,  # relative, cycle-to-cycle
    # smooth valve events: tanh transitions, centre and width in deg
    "ivc_width": 10.0,         # closed-cycle weight rises around theta_ivc
    "blowdown_centre": 155.0,  # closed-cycle weight falls (exhaust valve opens ~130 deg)
    "blowdown_width": 12.0,
    "exhaust_rise_centre": 140.0,   # gas-exchange pressure rises to p_exhaust ...
    "exhaust_rise_width": 12.0,
    "overlap_centre": 370.0,        # ... and falls to p_intake after the gas-exchange TDC
    "overlap_width": 8.0,
}

TARGET_SPEED = 130.0       # rad/s, tuning target of the mean heat release
STEP = 2.0e-6              # s, RK4 step
CROSSING_TOL = 1.0e-12     # s
CONVERGENCE_LIMIT = 1.0e-7 # rad/s
WARMUP_CYCLES = 20
RECORDED_CYCLES = 10
SAMPLES_PER_DEG = 2        # 0.5 deg sampling
SAMPLES_PER_CYCLE = 720 * SAMPLES_PER_DEG
DALPHA = math.radians(0.5)

NOISE_STD_P = 0.02         # bar
NOISE_STD_OMEGA = 0.08     # rad/s

COLUMNS = ["t", "crank_deg", "p_cyl1", "p_cyl2", "p_cyl3", "p_cyl4", "omega_dw", "omega_fw"]


def firing_position(cyl):
    """0-based position of cylinder `cyl` in the firing order (cyl1 0, cyl3 1, ...)."""
    return CONSTANTS["firing_order"].index(cyl)


def roundtrip(x):
    return float(FMT % x)


# --------------------------------------------------------------------------------------
# Piston kinematics and the single-zone pressure model
# --------------------------------------------------------------------------------------

R = CONSTANTS["crank_radius"]
L = CONSTANTS["rod_length"]
AREA = math.pi * CONSTANTS["bore"] ** 2 / 4.0
V_DISP = AREA * 2.0 * R
V_CLEAR = V_DISP / (PRESSURE_MODEL["compression_ratio"] - 1.0)


def piston_travel(phi):
    """s(phi) = r (1 - cos phi) + l - sqrt(l^2 - r^2 sin^2 phi), from TDC [m]."""
    sn = math.sin(phi)
    return R * (1.0 - math.cos(phi)) + L - math.sqrt(L * L - R * R * sn * sn)


def piston_travel_derivative(phi):
    """s'(phi) = ds/dphi [m/rad] (the seed's eq. 4 lever arm, sin^2 phi under the root)."""
    sn = math.sin(phi)
    return R * sn + R * R * math.sin(2.0 * phi) / (2.0 * math.sqrt(L * L - R * R * sn * sn))


def cylinder_volume(phi):
    return V_CLEAR + AREA * piston_travel(phi)


def cylinder_pressure(theta_deg, heat_release, theta_soc):
    """Absolute pressure [Pa] at local angle theta_deg in [-360, 360) (0 = firing TDC),
    for one cycle with the given heat release [J] and start of combustion [deg]."""
    pm = PRESSURE_MODEL
    p_in, p_ex = pm["p_intake"], pm["p_exhaust"]
    v = cylinder_volume(math.radians(theta_deg))
    v_ivc = cylinder_volume(math.radians(pm["theta_ivc"]))
    kc, ke = pm["kappa_compression"], pm["kappa_expansion"]
    # Compression polytrope from intake valve closing.
    p_comp = p_in * (v_ivc / v) ** kc
    # Expansion polytrope from the TDC state raised by the heat released at constant
    # volume: p3 = p2 + (gamma - 1) Q / Vc  (Eriksson & Andersson, p3 = p2 T3/T2).
    p2 = p_in * (v_ivc / V_CLEAR) ** kc
    p3 = p2 + (ke - 1.0) * heat_release / V_CLEAR
    p_exp = p3 * (V_CLEAR / v) ** ke
    # Wiebe burn fraction.
    u = (theta_deg - theta_soc) / pm["burn_duration"]
    xb = 1.0 - math.exp(-pm["wiebe_a"] * u ** (pm["wiebe_m"] + 1.0)) if u > 0.0 else 0.0
    p_closed = (1.0 - xb) * p_comp + xb * p_exp
    # Smooth valve events: weight of the closed cycle (rises at IVC, falls in the blowdown).
    w_closed = (0.5 * (1.0 + math.tanh((theta_deg - pm["theta_ivc"]) / pm["ivc_width"]))
                * 0.5 * (1.0 - math.tanh((theta_deg - pm["blowdown_centre"]) / pm["blowdown_width"])))
    # Gas exchange, angle psi in [0, 720) from the firing TDC: exhaust stroke p_ex,
    # intake stroke p_in, smooth change over the gas-exchange TDC (psi = 360).
    psi = theta_deg % 720.0
    e = (0.5 * (1.0 + math.tanh((psi - pm["exhaust_rise_centre"]) / pm["exhaust_rise_width"]))
         * 0.5 * (1.0 - math.tanh((psi - pm["overlap_centre"]) / pm["overlap_width"])))
    p_gas_exchange = p_in + (p_ex - p_in) * e
    return w_closed * p_closed + (1.0 - w_closed) * p_gas_exchange


def indicated_work(heat_release, theta_soc, n=14400):
    """Indicated work of one cylinder over one 720 deg cycle [J] (midpoint rule)."""
    h = 720.0 / n
    w = 0.0
    for i in range(n):
        th = -360.0 + (i + 0.5) * h
        w += (cylinder_pressure(th, heat_release, theta_soc) - CONSTANTS["p_atm"]) \
            * AREA * piston_travel_derivative(math.radians(th))
    return w * math.radians(h)


def tune_heat_release(params):
    """Mean heat release per cylinder and cycle [J] such that the mean indicated torque
    (4 cylinders, one cycle = 4 pi rad) balances the friction at TARGET_SPEED.
    The work is affine in the heat release, so two evaluations solve it."""
    soc = PRESSURE_MODEL["theta_soc_mean"]
    c_sum = params["C1"] + CONSTANTS["cylinders"] * params["C2"] + params["C3"]
    torque = c_sum * TARGET_SPEED
    w_needed = torque * 4.0 * math.pi / CONSTANTS["cylinders"]
    w0 = indicated_work(0.0, soc)
    w1 = indicated_work(100.0, soc)
    slope = (w1 - w0) / 100.0
    q = (w_needed - w0) / slope
    # For the README: the heat release a 15 bar peak would need, and what it implies.
    lo, hi = q, 10.0 * q
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if peak_pressure(mid, soc) < 15.0e5:
            lo = mid
        else:
            hi = mid
    t15 = CONSTANTS["cylinders"] * (w0 + slope * lo) / (4.0 * math.pi)
    return q, {"friction_torque": torque, "work_per_cycle": w_needed,
               "imep_net_bar": w_needed / V_DISP / 1e5,
               "pumping_and_motored_work": w0,
               "peak_pressure_bar": peak_pressure(q, soc) / 1e5,
               "heat_release_for_15bar_peak": lo, "torque_for_15bar_peak": t15,
               "speed_for_15bar_peak": t15 / c_sum,
               "friction_factor_for_15bar_peak_at_target": t15 / torque}


def peak_pressure(heat_release, theta_soc):
    """Largest pressure of a cycle on a 0.1 deg grid [Pa]."""
    return max(cylinder_pressure(-360.0 + 0.1 * i, heat_release, theta_soc) for i in range(7200))


# --------------------------------------------------------------------------------------
# Pressure tables over the global crank-angle grid alpha_j = j * 0.5 deg
# --------------------------------------------------------------------------------------


def cycle_of(cyl, j):
    """(cycle index n, local angle in half-degrees in [-720, 720)) of cylinder cyl at
    grid index j; cycle n of cylinder c spans local angles around its firing TDC at
    crank angle 720 n + 180 k_c deg."""
    jd = j - 360 * firing_position(cyl)
    n = (jd + 720) // 1440
    return n, jd - 1440 * n


def draw_combustion(n_last, q_mean):
    """Heat release and start of combustion for every combustion event, drawn in
    chronological order (cycle n = -1, 0, 1, ..., cylinders in firing order) from
    random.Random(SEED): gauss for the heat release, then gauss for theta_soc."""
    rng = random.Random(SEED)
    pm = PRESSURE_MODEL
    events = {}
    for n in range(-1, n_last + 1):
        for cyl in CONSTANTS["firing_order"]:
            q = q_mean * (1.0 + pm["heat_release_std"] * rng.gauss(0.0, 1.0))
            soc = pm["theta_soc_mean"] + pm["theta_soc_std"] * rng.gauss(0.0, 1.0)
            events[(cyl, n)] = (q, soc)
    return events


def build_tables(j_max, q_mean):
    """Pressure tables for cylinders 1..4 at j = 0..j_max: in bar as written (%.10g)
    and in Pa (= written bar value * 1e5, what the simulation interpolates), plus the
    combustion events used."""
    n_last = max(cycle_of(c, j_max)[0] for c in range(1, 5))
    events = draw_combustion(n_last, q_mean)
    tables_bar, tables_pa = {}, {}
    for cyl in range(1, 5):
        tab = []
        for j in range(j_max + 1):
            n, loc = cycle_of(cyl, j)
            q, soc = events[(cyl, n)]
            tab.append(roundtrip(cylinder_pressure(0.5 * loc, q, soc) / 1e5))
        tables_bar[cyl] = tab
        tables_pa[cyl] = [x * 1e5 for x in tab]
    return tables_bar, tables_pa, events


# --------------------------------------------------------------------------------------
# The engine-block model (the methodology paper eqs. 1-4) and its RK4 integration
# --------------------------------------------------------------------------------------


def make_acceleration(p, tables):
    """Right-hand side: accelerations of the six nodes from angles and speeds."""
    J1, J2, J3, m = p["J1"], p["J2"], p["J3"], p["m"]
    C1, C2, C3 = p["C1"], p["C2"], p["C3"]
    C21, C32, Cxx = p["C21"], p["C32"], p["Cxx"]
    K21, Kxx, K32 = CONSTANTS["K21"], CONSTANTS["Kxx"], CONSTANTS["K32"]
    p_atm = CONSTANTS["p_atm"]
    r, rr, r4, ll = R, R * R, R ** 4, L * L
    area = AREA
    inv_da = 1.0 / DALPHA
    sin, cos, sqrt = math.sin, math.cos, math.sqrt

    def throw(theta, omega, tab, slope, offset):
        """Gas + centripetal reciprocating torque on a throw, and its effective inertia."""
        x = theta * inv_da
        j = int(x)
        pr = tab[j] + (x - j) * slope[j]
        phi = theta - offset
        sn = sin(phi)
        cs = cos(phi)
        q = ll - rr * sn * sn
        sq = sqrt(q)
        s2 = 2.0 * sn * cs
        ds = r * sn + rr * s2 / (2.0 * sq)
        dds = r * cs + rr * (1.0 - 2.0 * sn * sn) / sq + r4 * s2 * s2 / (4.0 * q * sq)
        return (pr - p_atm) * area * ds - m * ds * dds * omega * omega, J2 + m * ds * ds

    slopes = {c: [b - a for a, b in zip(tables[c], tables[c][1:])] + [0.0] for c in tables}
    t1, t2, t3, t4 = (tables[c] for c in (1, 2, 3, 4))
    s1, s2_, s3, s4 = (slopes[c] for c in (1, 2, 3, 4))
    o1, o2, o3, o4 = (firing_position(c) * math.pi for c in (1, 2, 3, 4))

    def acc(th, w):
        a0, a1, a2, a3, a4, a5 = th
        w0, w1, w2, w3, w4, w5 = w
        if a1 < 0.0 or a2 < 0.0 or a3 < 0.0 or a4 < 0.0:
            raise RuntimeError("throw angle below the pressure table")
        e0 = K21 * (a0 - a1) + C21 * (w0 - w1)
        e1 = Kxx * (a1 - a2) + Cxx * (w1 - w2)
        e2 = Kxx * (a2 - a3) + Cxx * (w2 - w3)
        e3 = Kxx * (a3 - a4) + Cxx * (w3 - w4)
        e4 = K32 * (a4 - a5) + C32 * (w4 - w5)
        g1, d1 = throw(a1, w1, t1, s1, o1)
        g2, d2 = throw(a2, w2, t2, s2_, o2)
        g3, d3 = throw(a3, w3, t3, s3, o3)
        g4, d4 = throw(a4, w4, t4, s4, o4)
        return ((-e0 - C1 * w0) / J1,
                (e0 - e1 - C2 * w1 + g1) / d1,
                (e1 - e2 - C2 * w2 + g2) / d2,
                (e2 - e3 - C2 * w3 + g3) / d3,
                (e3 - e4 - C2 * w4 + g4) / d4,
                (e4 - C3 * w5) / J3)

    return acc


def rk4_step(acc, th, th_lo, w, w_lo, h):
    """One classic RK4 step of size h for theta' = w, w' = acc(theta, w).

    Angles and speeds are carried as unevaluated sums hi + lo (compensated
    summation): the angles grow to several hundred rad while a step adds about
    3e-4 rad, and without compensation the rounding of a million additions would
    shift the flywheel angle (and so the sample times) by more than the truncation
    error of the step."""
    hh = 0.5 * h
    k1 = acc([x + e for x, e in zip(th, th_lo)], [v + f for v, f in zip(w, w_lo)])
    th2 = [x + (e + hh * v) for x, e, v in zip(th, th_lo, w)]
    w2 = [v + (f + hh * a) for v, f, a in zip(w, w_lo, k1)]
    k2 = acc(th2, w2)
    th3 = [x + (e + hh * v) for x, e, v in zip(th, th_lo, w2)]
    w3 = [v + (f + hh * a) for v, f, a in zip(w, w_lo, k2)]
    k3 = acc(th3, w3)
    th4 = [x + (e + h * v) for x, e, v in zip(th, th_lo, w3)]
    w4 = [v + (f + h * a) for v, f, a in zip(w, w_lo, k3)]
    k4 = acc(th4, w4)
    h6 = h / 6.0
    # increments, then two-sum into (hi, lo)
    y = [e + h6 * (v1 + 2.0 * (v2 + v3) + v4)
         for e, v1, v2, v3, v4 in zip(th_lo, w, w2, w3, w4)]
    th_n = [x + d for x, d in zip(th, y)]
    th_lo_n = [d - (s - x) for x, d, s in zip(th, y, th_n)]
    z = [f + h6 * (b1 + 2.0 * (b2 + b3) + b4)
         for f, b1, b2, b3, b4 in zip(w_lo, k1, k2, k3, k4)]
    w_n = [v + d for v, d in zip(w, z)]
    w_lo_n = [d - (s - v) for v, d, s in zip(w, z, w_n)]
    return th_n, th_lo_n, w_n, w_lo_n


def hermite_crossing(y0, v0, y1, v1, h, target):
    """tau in [0, h] where the cubic Hermite interpolant of (y0, v0) -> (y1, v1) over a
    step h reaches target (Newton from the linear estimate)."""
    tau = h * (target - y0) / (y1 - y0)
    for _ in range(20):
        s = tau / h
        h00 = 2 * s ** 3 - 3 * s ** 2 + 1
        h10 = s ** 3 - 2 * s ** 2 + s
        h01 = -2 * s ** 3 + 3 * s ** 2
        h11 = s ** 3 - s ** 2
        y = h00 * y0 + h10 * h * v0 + h01 * y1 + h11 * h * v1
        dy = ((6 * s ** 2 - 6 * s) * y0 + (3 * s ** 2 - 4 * s + 1) * h * v0
              + (-6 * s ** 2 + 6 * s) * y1 + (3 * s ** 2 - 2 * s) * h * v1) / h
        d = (y - target) / dy
        tau -= d
        if abs(d) < 1e-15:
            break
    return min(max(tau, 0.0), h)


def advance(acc, state, h):
    """Advance the state (th, th_lo, w, w_lo) by h with RK4, split at the kinks.

    The pressure is linear between the grid angles alpha_j, so the right-hand side
    has a slope discontinuity each time a throw angle crosses a grid angle. An RK4
    step across such a kink is only second-order accurate and its error depends
    erratically on where the kink falls, which spoils the step-halving convergence.
    So a trial step finds the throws' grid crossings inside [0, h] (cubic Hermite
    of the throw angle), and if there are any the step is redone in pieces that end
    exactly at them."""
    th, th_lo, w, w_lo = state
    new = rk4_step(acc, th, th_lo, w, w_lo, h)
    kinks = []
    for i in (1, 2, 3, 4):
        a0 = th[i] + th_lo[i]
        a1 = new[0][i] + new[1][i]
        j0 = math.floor(a0 / DALPHA)
        j1 = math.floor(a1 / DALPHA)
        for jj in range(j0 + 1, j1 + 1):
            tk = hermite_crossing(a0, w[i] + w_lo[i], a1, new[2][i] + new[3][i], h, jj * DALPHA)
            if 0.0 < tk < h:
                kinks.append(tk)
    if not kinks:
        return new
    kinks.sort()
    done = 0.0
    for tk in kinks + [h]:
        if tk - done > 0.0:
            state = rk4_step(acc, state[0], state[1], state[2], state[3], tk - done)
            done = tk
    return state


def simulate(params, tables, step, j_first, j_last, omega0, probe_stride=0, start=None):
    """Integrate from theta = 0, w = omega0 (all nodes), or from start = (th, w) at
    t = 0, until the flywheel angle passes alpha_{j_last}; return the samples
    j_first..j_last (and, before j_first, every probe_stride-th one, to watch the
    warm-up) as a list of (j, t, th[6], w[6]) at the flywheel crossings of
    alpha_j = j * 0.5 deg."""
    acc = make_acceleration(params, tables)
    if start is None:
        state = ([0.0] * 6, [0.0] * 6, [float(omega0)] * 6, [0.0] * 6)
    else:
        state = (list(start[0]), [0.0] * 6, list(start[1]), [0.0] * 6)
    n = 0
    j = probe_stride if 0 < probe_stride < j_first else j_first
    target = j * DALPHA
    out = []
    while j <= j_last:
        new = advance(acc, state, step)
        while j <= j_last and new[0][5] + new[1][5] >= target:
            # Sample inside [n h, (n+1) h]: Hermite estimate, then Newton on the
            # partial step from the step start (its flywheel angle hits target).
            th, th_lo, w, w_lo = state
            tau = hermite_crossing(th[5] + th_lo[5], w[5] + w_lo[5],
                                   new[0][5] + new[1][5], new[2][5] + new[3][5], step, target)
            for _ in range(30):
                part = advance(acc, state, tau)
                delta = ((part[0][5] - target) + part[1][5]) / (part[2][5] + part[3][5])
                tau -= delta
                if abs(delta) < CROSSING_TOL:
                    part = advance(acc, state, tau)
                    break
            else:
                raise RuntimeError("crossing of sample %d not located" % j)
            out.append((j, n * step + tau,
                        [x + e for x, e in zip(part[0], part[1])],
                        [v + f for v, f in zip(part[2], part[3])]))
            if probe_stride and j + probe_stride < j_first:
                j += probe_stride
            else:
                j = max(j + 1, j_first)
            target = j * DALPHA
        state = new
        n += 1
    return out


def sensitivity_check(params, tables, step, rec):
    """RMS change of omega_dw over the first recorded cycle when one parameter is
    raised by 1 %, simulated from the exact state at the first recorded sample with
    the same pressures (how strongly each parameter shows in the output)."""
    j0 = rec[0][0]
    start = (rec[0][2], rec[0][3])
    j_end = j0 + SAMPLES_PER_CYCLE - 1
    base = simulate(params, tables, step, j0 + 1, j_end, 0.0, 0, start)
    out = {}
    for name in PARAM_NAMES:
        p = dict(params)
        p[name] *= 1.01
        pert = simulate(p, tables, step, j0 + 1, j_end, 0.0, 0, start)
        out[name] = math.sqrt(sum((a[3][0] - b[3][0]) ** 2 for a, b in zip(pert, base))
                              / len(base))
    return out


def run_simulation(args):
    """Worker entry (the half-step check runs in a second process). With
    with_sensitivity, the 1 % sensitivities of the first recorded cycle follow."""
    params, tables, step, j_first, j_last, omega0, probe_stride, with_sensitivity = args
    t0 = time.time()
    res = simulate(params, tables, step, j_first, j_last, omega0, probe_stride)
    elapsed = time.time() - t0
    sens = None
    if with_sensitivity:
        rec = [s for s in res if s[0] >= j_first]
        sens = sensitivity_check(params, tables, step, rec)
    return res, elapsed, sens


# --------------------------------------------------------------------------------------
# Files
# --------------------------------------------------------------------------------------

NODE_NAMES = ["damping_wheel", "throw1", "throw2", "throw3", "throw4", "flywheel"]
PROBE_STRIDE = 8   # warm-up: every 4 deg a sample, only to report the settling


def write_csv(path, header_lines, rows):
    with open(path, "w", newline="\n") as f:
        for line in header_lines:
            f.write("# " + line + "\n")
        f.write(",".join(COLUMNS) + "\n")
        for row in rows:
            f.write(",".join(FMT % x for x in row) + "\n")


def read_csv(path):
    cols = None
    data = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            if cols is None:
                cols = line.split(",")
                assert cols == COLUMNS, cols
                continue
            data.append([float(x) for x in line.split(",")])
    return {c: [row[i] for row in data] for i, c in enumerate(cols)}


def max_abs(values):
    return max(abs(x) for x in values)


def cycle_slices(n_rows):
    return [range(k * SAMPLES_PER_CYCLE, min((k + 1) * SAMPLES_PER_CYCLE, n_rows))
            for k in range((n_rows + SAMPLES_PER_CYCLE - 1) // SAMPLES_PER_CYCLE)]


def main(argv=None):
    wall0 = time.time()
    repo_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(repo_root, "data", "engine"),
                    help="output folder (default: <repo>/data/engine)")
    ap.add_argument("--quiet", action="store_true", help="do not print the summary")
    args = ap.parse_args(argv)
    out = args.out
    say = (lambda *a: None) if args.quiet else (lambda *a: print(*a, flush=True))
    p = dict(TRUE_PARAMS)

    # 1. Combustion: mean heat release for 130 rad/s, then the pressure tables.
    q_mean, tune = tune_heat_release(p)
    j0 = WARMUP_CYCLES * SAMPLES_PER_CYCLE            # first recorded grid index
    n_rows = RECORDED_CYCLES * SAMPLES_PER_CYCLE
    j_last = j0 + n_rows - 1
    j_max = j_last + SAMPLES_PER_CYCLE                # margin: throws run ahead
    tab_bar, tab_pa, events = build_tables(j_max, q_mean)
    say("mean heat release %.4f J per cylinder and cycle (friction torque %.4f N m at %g rad/s,"
        " net IMEP %.4f bar)" % (q_mean, tune["friction_torque"], TARGET_SPEED, tune["imep_net_bar"]))

    # 2. Simulation with STEP and, in parallel, with STEP/2 for the convergence check.
    say("simulating %d + %d cycles with RK4 steps of %g s and %g s ..."
        % (WARMUP_CYCLES, RECORDED_CYCLES, STEP, STEP / 2))
    jobs = [(p, tab_pa, STEP / 2, j0, j_last, TARGET_SPEED, 0, False),
            (p, tab_pa, STEP, j0, j_last, TARGET_SPEED, PROBE_STRIDE, True)]
    with concurrent.futures.ProcessPoolExecutor(max_workers=2) as pool:
        (half, t_half, _), (full, t_full, sens) = pool.map(run_simulation, jobs)
    probes = [s for s in full if s[0] < j0]
    rec = [s for s in full if s[0] >= j0]
    assert [s[0] for s in rec] == list(range(j0, j_last + 1))
    assert [s[0] for s in half] == list(range(j0, j_last + 1))
    conv = {
        "step": STEP, "half_step": STEP / 2,
        "max_abs_diff_omega_dw": max_abs([a[3][0] - b[3][0] for a, b in zip(rec, half)]),
        "max_abs_diff_omega_fw": max_abs([a[3][5] - b[3][5] for a, b in zip(rec, half)]),
        "max_abs_diff_t": max_abs([a[1] - b[1] for a, b in zip(rec, half)]),
        "limit": CONVERGENCE_LIMIT,
    }
    conv["passed"] = max(conv["max_abs_diff_omega_dw"], conv["max_abs_diff_omega_fw"]) < CONVERGENCE_LIMIT
    say("convergence check (whole run, step %g s vs %g s): max |d omega_dw| = %.3g rad/s, "
        "max |d omega_fw| = %.3g rad/s, max |d t| = %.3g s -> %s"
        % (STEP, STEP / 2, conv["max_abs_diff_omega_dw"], conv["max_abs_diff_omega_fw"],
           conv["max_abs_diff_t"], "OK" if conv["passed"] else "FAILED"))
    if not conv["passed"]:
        print("error: the recorded speeds are not converged in the step; nothing written",
              file=sys.stderr)
        return 1

    # 3. Rows, re-based: crank_deg 0 = first recorded sample = cylinder 1 firing TDC.
    t_first = rec[0][1]
    alpha0 = j0 * DALPHA
    clean = []
    for j, t, th, w in rec:
        clean.append([t - t_first, 0.5 * (j - j0)]
                     + [tab_bar[c][j] for c in (1, 2, 3, 4)] + [w[0], w[5]])
    clean = [[roundtrip(x) for x in row] for row in clean]

    rng = random.Random(NOISE_SEED)
    noisy = [list(row) for row in clean]
    for col, std in ((2, NOISE_STD_P), (3, NOISE_STD_P), (4, NOISE_STD_P), (5, NOISE_STD_P),
                     (6, NOISE_STD_OMEGA), (7, NOISE_STD_OMEGA)):
        for row in noisy:
            row[col] += rng.gauss(0.0, std)

    os.makedirs(out, exist_ok=True)
    common = [
        "Engine-block idle (the methodology paper), synthetic reference data, %d cycles of 720 deg."
        % RECORDED_CYCLES,
        "Sampled every 0.5 deg of FLYWHEEL angle (crank_deg, cumulative; 0 = cylinder 1 firing TDC);",
        "time stamps t are therefore not uniform. Firing order 1-3-4-2.",
        "Units: t in s, crank_deg in deg, p_cyl1..p_cyl4 in bar (absolute), omega_dw",
        "(damping wheel) and omega_fw (flywheel) in rad/s.",
        "Speeds: engine_block model with the true parameters of truth.json, driven by the",
        "noise-free pressure columns (linear in crank angle, looked up by each throw's angle).",
        "Generated by %s (deterministic, seeds %d/%d)." % (SCRIPT_NAME, SEED, NOISE_SEED),
    ]
    clean_path = os.path.join(out, "idle_clean.csv")
    noisy_path = os.path.join(out, "idle.csv")
    write_csv(clean_path, ["NOISE-FREE twin of idle.csv."] + common + ["Noise: none."], clean)
    write_csv(noisy_path, ["Recording with measurement noise."] + common
              + ["Noise: Gaussian white, std %g bar on each pressure, %g rad/s on each speed;"
                 % (NOISE_STD_P, NOISE_STD_OMEGA),
                 "       t and crank_deg are exact. Noise-free twin: idle_clean.csv."], noisy)

    # 4. Statistics and reference figures, from the files as written.
    fc = read_csv(clean_path)
    fn = read_csv(noisy_path)
    slices = cycle_slices(n_rows)
    dw, fw = fc["omega_dw"], fc["omega_fw"]
    per_cycle = []
    for k, sl in enumerate(slices):
        res = [fn["omega_dw"][i] - dw[i] for i in sl]
        ratio = [(fn["omega_dw"][i] - dw[i]) / fn["omega_dw"][i] for i in sl]
        per_cycle.append({
            "cycle": k,
            "crank_deg": [fc["crank_deg"][sl[0]], fc["crank_deg"][sl[-1]]],
            "t": [fc["t"][sl[0]], fc["t"][sl[-1]]],
            "mean_omega_dw": sum(dw[i] for i in sl) / len(sl),
            "ripple_p2p_omega_dw": max(dw[i] for i in sl) - min(dw[i] for i in sl),
            "ripple_p2p_omega_fw": max(fw[i] for i in sl) - min(fw[i] for i in sl),
            "peak_pressure_bar": {"p_cyl%d" % c: max(fc["p_cyl%d" % c][i] for i in sl)
                                  for c in (1, 2, 3, 4)},
            "max_abs_residual_ratio": max_abs(ratio),
            "rmse_omega_dw": math.sqrt(sum(e * e for e in res) / len(res)),
            "sum_sq_omega_dw": sum(e * e for e in res),
        })
    warm_cycles = []
    for k in range(WARMUP_CYCLES):
        ws = [s[3][0] for s in probes if k * SAMPLES_PER_CYCLE <= s[0] < (k + 1) * SAMPLES_PER_CYCLE]
        if ws:
            warm_cycles.append(sum(ws) / len(ws))
    peaks = [pc["peak_pressure_bar"]["p_cyl%d" % c] for pc in per_cycle for c in (1, 2, 3, 4)]
    dp = max(max_abs([b - a for a, b in zip(fc["p_cyl%d" % c], fc["p_cyl%d" % c][1:])])
             for c in (1, 2, 3, 4))
    twist_wheel = max_abs([s[2][0] - s[2][1] for s in rec])
    twist_crank = max_abs([s[2][1] - s[2][5] for s in rec])
    lag0 = [rec[0][2][i] - alpha0 for i in range(6)]
    t_end = rec[-1][1] - t_first
    # combustion events whose firing TDC lies in the record
    rec_events = [events[(c, n)] for (c, n) in events
                  if j0 <= (1440 * n + 360 * firing_position(c)) <= j_last]
    stats = {
        "rows": n_rows,
        "duration_s": t_end,
        "mean_omega_dw": sum(dw) / len(dw),
        "mean_omega_fw": sum(fw) / len(fw),
        "omega_dw_range": [min(dw), max(dw)],
        "omega_fw_range": [min(fw), max(fw)],
        "ripple_p2p_omega_dw_mean": sum(c["ripple_p2p_omega_dw"] for c in per_cycle) / len(per_cycle),
        "ripple_p2p_omega_dw_max": max(c["ripple_p2p_omega_dw"] for c in per_cycle),
        "ripple_p2p_omega_fw_mean": sum(c["ripple_p2p_omega_fw"] for c in per_cycle) / len(per_cycle),
        "cycle_mean_omega_dw": [c["mean_omega_dw"] for c in per_cycle],
        "warmup_cycle_mean_omega_dw": warm_cycles,
        "peak_pressure_bar": {"min": min(peaks), "mean": sum(peaks) / len(peaks), "max": max(peaks)},
        "max_pressure_step_between_samples_bar": dp,
        "max_twist_wheel_throw1_rad": twist_wheel,
        "max_twist_throw1_flywheel_rad": twist_crank,
        "heat_release_recorded_J": [min(e[0] for e in rec_events), max(e[0] for e in rec_events)],
        "theta_soc_recorded_deg": [min(e[1] for e in rec_events), max(e[1] for e in rec_events)],
    }

    truth = {
        "model": "engine_block",
        "constants": dict(CONSTANTS),
        "parameters": {k: p[k] for k in PARAM_NAMES},
        "parameter_units": UNITS,
        "firing_order": CONSTANTS["firing_order"],
        "nodes": NODE_NAMES,
        "noise_std": {"p_cyl1": NOISE_STD_P, "p_cyl2": NOISE_STD_P, "p_cyl3": NOISE_STD_P,
                      "p_cyl4": NOISE_STD_P, "omega_dw": NOISE_STD_OMEGA,
                      "omega_fw": NOISE_STD_OMEGA, "units": "bar, rad/s"},
        "seed": SEED,
        "noise_seed": NOISE_SEED,
        "sampling": {"angle_column": "crank_deg", "angle_of": "flywheel", "step_deg": 0.5,
                     "samples_per_cycle": SAMPLES_PER_CYCLE, "rows": n_rows,
                     "crank_deg_0": "cylinder 1 firing TDC"},
        "cycles_recorded": RECORDED_CYCLES,
        "warmup_cycles": WARMUP_CYCLES,
        "files": {"noisy": "idle.csv", "clean": "idle_clean.csv"},
        "columns": COLUMNS,
        "generator": SCRIPT_NAME,
        "pressure_model": dict(PRESSURE_MODEL, heat_release_mean=q_mean,
                               clearance_volume=V_CLEAR, displacement_per_cylinder=V_DISP,
                               units="Pa, deg, J, m^3"),
        "operating_point": dict(tune, target_speed=TARGET_SPEED),
        "simulation": {
            "method": "rk4", "step": STEP,
            "kinks": "steps split where a throw angle crosses a 0.5 deg grid angle",
            "sample_time_tolerance": CROSSING_TOL,
            "initial_state": "all nodes theta = 0, omega = %g rad/s at crank angle 0" % TARGET_SPEED,
            "rebase_deg": 0.5 * j0,
        },
        "convergence_check": conv,
        "sensitivity_1_percent": {
            "definition": ("RMS change of omega_dw over recorded cycle 0 when one parameter "
                           "is raised by 1 %, simulated from state_at_first_sample with the "
                           "same pressures [rad/s]"),
            "rms_change_omega_dw": sens},
        "mean_omega_dw": stats["mean_omega_dw"],
        "ripple_p2p_omega_dw": stats["ripple_p2p_omega_dw_mean"],
        "statistics": stats,
        "state_at_first_sample": {
            "t": 0.0,
            "theta_rad": dict(zip(NODE_NAMES, lag0)),
            "omega_rad_s": dict(zip(NODE_NAMES, rec[0][3])),
            "note": "angles re-based like crank_deg (flywheel = 0 exactly)",
        },
        "reference_residuals": {
            "definition": ("true parameters: omega_dw of idle_clean.csv is the model output; "
                           "per recorded cycle k (crank_deg in [720k, 720k+720)): "
                           "max |(omega_dw_noisy - omega_dw_clean) / omega_dw_noisy|, RMSE and "
                           "sum of squares of omega_dw_noisy - omega_dw_clean (the methodology paper Fig. 2b, eq. 7)"),
            "file": "idle.csv",
            "max_abs_residual_ratio": max(c["max_abs_residual_ratio"] for c in per_cycle),
            "per_cycle": [{k: c[k] for k in ("cycle", "crank_deg", "t", "max_abs_residual_ratio",
                                             "rmse_omega_dw", "sum_sq_omega_dw")}
                          for c in per_cycle],
        },
    }
    with open(os.path.join(out, "truth.json"), "w", newline="\n") as f:
        json.dump(truth, f, indent=2)
        f.write("\n")
    with open(os.path.join(out, "README.md"), "w", newline="\n") as f:
        f.write(readme_text(p, q_mean, tune, stats, per_cycle, conv, lag0, sens))

    say("rows %d (%d cycles, %.4f s), mean omega_dw %.4f rad/s, mean omega_fw %.4f rad/s"
        % (n_rows, RECORDED_CYCLES, t_end, stats["mean_omega_dw"], stats["mean_omega_fw"]))
    say("cycle means omega_dw: " + " ".join("%.3f" % x for x in stats["cycle_mean_omega_dw"]))
    say("warm-up cycle means:  " + " ".join("%.3f" % x for x in warm_cycles))
    say("ripple p2p omega_dw: mean %.4f, max %.4f rad/s; omega_fw: mean %.4f rad/s"
        % (stats["ripple_p2p_omega_dw_mean"], stats["ripple_p2p_omega_dw_max"],
           stats["ripple_p2p_omega_fw_mean"]))
    say("peak pressures: min %.3f, mean %.3f, max %.3f bar; max step between samples %.4f bar"
        % (stats["peak_pressure_bar"]["min"], stats["peak_pressure_bar"]["mean"],
           stats["peak_pressure_bar"]["max"], dp))
    say("max twist: wheel-throw1 %.3g rad, throw1-flywheel %.3g rad"
        % (twist_wheel, twist_crank))
    say("max |residual ratio| (noisy vs true) per cycle: "
        + " ".join("%.5f" % c["max_abs_residual_ratio"] for c in per_cycle))
    say("RMS change of omega_dw for +1 % of a parameter: "
        + ", ".join("%s %.2g" % (k, sens[k]) for k in PARAM_NAMES))
    say("simulation %.1f s (step %g) and %.1f s (step %g), total runtime %.1f s"
        % (t_full, STEP, t_half, STEP / 2, time.time() - wall0))
    return 0


def readme_text(p, q_mean, tune, st, per_cycle, conv, lag0, sens):
    pm = PRESSURE_MODEL
    slines = "\n".join("| %s | %.2g |" % (k, sens[k]) for k in PARAM_NAMES)
    plines = "\n".join("| %s | %.10g | %s |" % (k, p[k], UNITS[k]) for k in PARAM_NAMES)
    clines = "\n".join(
        "| %d | %.1f-%.1f | %.4f-%.4f | %.3f | %.3f | %.3f | %.2f %.2f %.2f %.2f | %.5f | %.4f |"
        % (c["cycle"], c["crank_deg"][0], c["crank_deg"][1], c["t"][0], c["t"][1],
           c["mean_omega_dw"], c["ripple_p2p_omega_dw"], c["ripple_p2p_omega_fw"],
           c["peak_pressure_bar"]["p_cyl1"], c["peak_pressure_bar"]["p_cyl2"],
           c["peak_pressure_bar"]["p_cyl3"], c["peak_pressure_bar"]["p_cyl4"],
           c["max_abs_residual_ratio"], c["rmse_omega_dw"])
        for c in per_cycle)
    kw = {
        "rows": st["rows"], "cycles": RECORDED_CYCLES, "warm": WARMUP_CYCLES,
        "dur": st["duration_s"], "plines": plines, "clines": clines,
        "B": CONSTANTS["bore"], "r": CONSTANTS["crank_radius"], "l": CONSTANTS["rod_length"],
        "patm": CONSTANTS["p_atm"], "K21": CONSTANTS["K21"], "Kxx": CONSTANTS["Kxx"],
        "K32": CONSTANTS["K32"], "eps": pm["compression_ratio"], "vd": V_DISP * 1e6,
        "vc": V_CLEAR * 1e6, "pin": pm["p_intake"] / 1e5, "pex": pm["p_exhaust"] / 1e5,
        "ivc": pm["theta_ivc"], "kc": pm["kappa_compression"], "ke": pm["kappa_expansion"],
        "soc": pm["theta_soc_mean"], "socstd": pm["theta_soc_std"], "dth": pm["burn_duration"],
        "wa": pm["wiebe_a"], "wm1": pm["wiebe_m"] + 1.0, "qstd": pm["heat_release_std"] * 100,
        "ivcw": pm["ivc_width"], "bdc": pm["blowdown_centre"], "bdw": pm["blowdown_width"],
        "exc": pm["exhaust_rise_centre"], "exw": pm["exhaust_rise_width"],
        "ovc": pm["overlap_centre"], "ovw": pm["overlap_width"],
        "q": q_mean, "tf": tune["friction_torque"], "imep": tune["imep_net_bar"],
        "w0": tune["pumping_and_motored_work"], "speed": TARGET_SPEED,
        "csum": p["C1"] + 4 * p["C2"] + p["C3"],
        "q15": tune["heat_release_for_15bar_peak"], "t15": tune["torque_for_15bar_peak"],
        "s15": tune["speed_for_15bar_peak"], "f15": tune["friction_factor_for_15bar_peak_at_target"],
        "seed": SEED, "nseed": NOISE_SEED, "sp": NOISE_STD_P, "so": NOISE_STD_OMEGA,
        "step": STEP * 1e6, "half": STEP * 0.5e6, "tol": CROSSING_TOL,
        "cdw": conv["max_abs_diff_omega_dw"], "cfw": conv["max_abs_diff_omega_fw"],
        "ct": conv["max_abs_diff_t"], "climit": CONVERGENCE_LIMIT,
        "mdw": st["mean_omega_dw"], "mfw": st["mean_omega_fw"],
        "dwlo": st["omega_dw_range"][0], "dwhi": st["omega_dw_range"][1],
        "rip": st["ripple_p2p_omega_dw_mean"], "ripmax": st["ripple_p2p_omega_dw_max"],
        "ripfw": st["ripple_p2p_omega_fw_mean"],
        "cmeans": ", ".join("%.2f" % x for x in st["cycle_mean_omega_dw"]),
        "wmeans": ", ".join("%.2f" % x for x in st["warmup_cycle_mean_omega_dw"]),
        "pkmin": st["peak_pressure_bar"]["min"], "pkmean": st["peak_pressure_bar"]["mean"],
        "pkmax": st["peak_pressure_bar"]["max"], "dp": st["max_pressure_step_between_samples_bar"],
        "tw1": st["max_twist_wheel_throw1_rad"], "tw2": st["max_twist_throw1_flywheel_rad"],
        "qlo": st["heat_release_recorded_J"][0], "qhi": st["heat_release_recorded_J"][1],
        "slo": st["theta_soc_recorded_deg"][0], "shi": st["theta_soc_recorded_deg"][1],
        "lagmin": -min(lag0[1:5]), "lagdeg": math.degrees(-min(lag0[1:5])),
        "rmax": max(c["max_abs_residual_ratio"] for c in per_cycle),
        "rebase": 0.5 * WARMUP_CYCLES * SAMPLES_PER_CYCLE,
        "slines": slines,
    }
    return """# Engine-block model: synthetic idle reference data

Synthetic stand-in for the idle recording of the methodology paper ("Methodology for Modeling,
Parameter Estimation, and Validation of Powertrain Torsional Vibration", Fig. 2:
four-cylinder engine, clutch disengaged, about 130 rad/s, in-cylinder pressures and
damping-wheel speed sampled every 0.5 deg of crank angle), generated by
`scripts/generate_engine_data.py`. The true parameters are known, so the
identification of the `engine_block` preset can be checked against them: a fit on
the noise-free file must recover them.

## Files

| file | content |
|---|---|
| `idle_clean.csv` | noise-free: columns `t,crank_deg,p_cyl1,p_cyl2,p_cyl3,p_cyl4,omega_dw,omega_fw` |
| `idle.csv` | the same recording with measurement noise (same columns) |
| `truth.json` | constants, true parameters, pressure-model settings, noise, seeds, statistics, reference residuals, the exact state at the first sample |

Both CSV files start with `#` comment lines, then the header row, then %(rows)d rows:
%(cycles)d consecutive 720 deg cycles, one row every 0.5 deg of **flywheel** angle,
`crank_deg` = 0, 0.5, ..., 7199.5 (cumulative; 0 = firing TDC of cylinder 1; cycle k
is `crank_deg` in [720 k, 720 k + 720)). The time stamps are therefore not uniform
(about 67 us apart); `t` starts at 0 at the first row and ends at %(dur).4f s.
Units: t in s, crank_deg in deg, p_cyl1..p_cyl4 in bar absolute, omega_dw (damping
wheel) and omega_fw (flywheel) in rad/s. Numbers are written with `%%.10g`.

## Model (the methodology paper eqs. 1-4, tvid preset `engine_block`)

Nodes (angle theta and speed w each, rad and rad/s, cumulative): 0 = damping wheel
(J1), 1..4 = crank throws of cylinders 1..4 in their physical order along the crank
(J2 each), 5 = flywheel (J3).

* spring-dampers: wheel-throw 1 (K21, C21), throw i - throw i+1 for i = 1..3
  (Kxx, Cxx), throw 4-flywheel (K32, C32); torque on a: -K (theta_a - theta_b) -
  C (w_a - w_b), the opposite on b;
* friction to ground: -C1 w on the wheel, -C2 w on each throw, -C3 w on the flywheel;
* a cylinder on each throw. Firing order 1-3-4-2: cylinder c has firing position
  k_c (cyl1 0, cyl3 1, cyl4 2, cyl2 3) and its firing TDC at crank angle
  k_c * 180 deg; its local crank angle is phi_c = theta_c - k_c * pi.

Piston kinematics (r crank radius, l rod length):

    s(phi)   = r (1 - cos phi) + l - sqrt(l^2 - r^2 sin^2 phi)
    s'(phi)  = r sin phi + r^2 sin 2phi / (2 sqrt(l^2 - r^2 sin^2 phi))
    s''(phi) = r cos phi + r^2 cos 2phi / sqrt(l^2 - r^2 sin^2 phi)
               + r^4 sin^2 2phi / (4 (l^2 - r^2 sin^2 phi)^(3/2))

Eq. 4 of the paper prints sin^2(2 theta) under the root; that is a typo: the
kinematics of the slider-crank have sin^2 phi there, as above.

Cylinder torque on throw c (gas force plus the exact reciprocating-mass force,
-m s'(phi) (s'(phi) theta_c'' + s''(phi) w_c^2)); the theta'' part is moved to the
left side:

    (J2 + m s'(phi_c)^2) theta_c'' = (spring, damper and friction torques on throw c)
                                    + (p_c - p_atm) (pi B^2 / 4) s'(phi_c)
                                    - m s'(phi_c) s''(phi_c) w_c^2

The pressure p_c acting on throw c is a function of the throw's **own** angle
theta_c (not of time): linear interpolation in the cylinder's pressure column over
the crank-angle grid alpha_j = j * 0.5 deg. The noise-free pressure columns of
`idle_clean.csv` are exactly the table the speeds were simulated with (values as
written, bar * 1e5 = Pa), continued before and after the recorded rows by the
same pressure model.

## Constants (fixed, not estimated)

| constant | value |
|---|---|
| cylinders | 4 |
| firing_order | 1-3-4-2 |
| bore B | %(B)g m |
| crank_radius r | %(r)g m |
| rod_length l | %(l)g m |
| p_atm | %(patm)g Pa |
| K21 | %(K21)g N m/rad |
| Kxx | %(Kxx)g N m/rad |
| K32 | %(K32)g N m/rad |

## True parameters

| parameter | value | unit |
|---|---|---|
%(plines)s

## Pressure model (per cylinder and 720 deg cycle)

Single-zone model after Eriksson & Andersson, as a function of the local angle
theta in [-360, 360) deg from the cylinder's firing TDC:

* volume V(theta) = Vc + (pi B^2/4) s(theta), compression ratio %(eps)g
  (Vd = %(vd).2f cm^3, Vc = Vd/(eps - 1) = %(vc).3f cm^3);
* compression polytrope from intake valve closing at %(ivc)g deg (30 deg ABDC):
  p_c = p_in (V_ivc/V)^%(kc)g, p_in = %(pin)g bar (throttled idle);
* combustion: Wiebe burn fraction x_b = 1 - exp(-%(wa)g u^%(wm1)g), u = (theta -
  theta_soc)/%(dth)g deg (x_b = 0 before theta_soc), mean theta_soc = %(soc)g deg;
* expansion polytrope from the TDC state raised by the heat released at constant
  volume: p3 = p_c(0) + (%(ke)g - 1) Q / Vc, p_e = p3 (Vc/V)^%(ke)g;
* closed cycle p = (1 - x_b) p_c + x_b p_e;
* valve events blended smoothly (tanh weights, no steps): the closed-cycle weight
  rises around IVC (%(ivc)g deg, width %(ivcw)g deg) and falls in the blowdown after
  the exhaust valve opens (centre %(bdc)g deg, width %(bdw)g deg); outside it the gas
  exchange pressure goes from p_in to p_ex = %(pex)g bar (exhaust stroke, centre
  %(exc)g deg, width %(exw)g deg) and back to p_in after the gas-exchange TDC
  (centre %(ovc)g deg, width %(ovw)g deg).

Cycle-to-cycle variation: for every combustion event, in firing sequence (cycle
n = -1, 0, 1, ..., cylinders 1, 3, 4, 2), `random.Random(%(seed)d)` draws the heat
release Q = Q_mean (1 + %(qstd)g %% * N(0,1)) and then theta_soc = %(soc)g deg +
%(socstd)g deg * N(0,1). In the recorded cycles Q is %(qlo).1f-%(qhi).1f J and theta_soc
%(slo).2f to %(shi).2f deg.

Mean heat release Q_mean = %(q).4f J per cylinder and cycle: the indicated work is
affine in Q, so Q_mean is solved exactly for a mean indicated torque (4 cylinders)
equal to the friction at %(speed)g rad/s, (C1 + 4 C2 + C3) * %(speed)g = %(tf).4f N m
(net IMEP %(imep).3f bar; the pumping and motored work without combustion is
%(w0).2f J per cylinder and cycle).

Peak pressures in the record are %(pkmin).2f-%(pkmax).2f bar (mean %(pkmean).2f bar),
below the 15-25 bar often quoted for idle: with the true friction coefficients the
engine needs only a net IMEP of about %(imep).1f bar to idle at %(speed)g rad/s. A 15 bar peak
needs Q = %(q15).0f J, which gives %(t15).1f N m of indicated torque, balanced by
C1 + 4 C2 + C3 = %(csum).3f N m s/rad only at %(s15).0f rad/s (or, at %(speed)g rad/s,
by friction coefficients %(f15).2f times larger). The parameters were left as
specified. The largest change between two neighbouring pressure samples is
%(dp).3f bar.

## Simulation and sampling

* Start: all nodes theta = 0 (crank angle 0 = cylinder 1 firing TDC),
  w = %(speed)g rad/s; %(warm)d warm-up cycles, then the %(cycles)d recorded cycles. The
  recorded angles are re-based by %(rebase)g deg (a multiple of 720 deg), so
  `crank_deg` 0 is again a firing TDC of cylinder 1, and the pressure table index
  is re-based with it (row i of the CSV is grid index i).
* Integration: classic RK4, fixed step %(step)g us (highest natural frequency about
  3e4 rad/s). The pressure table makes the right-hand side piecewise smooth
  (slope changes whenever a throw angle crosses a grid angle); a step containing
  such a crossing is split there (crossing located by cubic Hermite
  interpolation of the throw angle), so the scheme keeps its fourth order.
  Angles and speeds are accumulated with compensated summation.
* Sampling: a sample is taken when the flywheel angle crosses alpha_j; the time is
  located to %(tol)g s (cubic Hermite inside the step, then Newton on a partial
  RK4 step from the step start) and the recorded speeds are the state of that
  partial step.
* Convergence check (whole run repeated with step %(half)g us): max |d omega_dw| =
  %(cdw).2g rad/s, max |d omega_fw| = %(cfw).2g rad/s, max |d t| = %(ct).2g s (limit
  %(climit)g rad/s).
* State at the first row (from truth.json, angles re-based): the throws are a
  little behind the flywheel (by up to %(lagmin).3g rad = %(lagdeg).4f deg), so a
  simulation started exactly at the first row needs the pressure at a throw angle
  just below `crank_deg` 0, which is not in the file; holding or extrapolating the
  first value changes the result negligibly, or start one cycle later.

## Noise

`idle.csv` = `idle_clean.csv` plus independent Gaussian white noise, standard
deviation %(sp)g bar on each pressure and %(so)g rad/s on each speed,
`random.Random(%(nseed)d)`, column by column (p_cyl1, p_cyl2, p_cyl3, p_cyl4,
omega_dw, omega_fw), each over all rows. `t` and `crank_deg` carry no noise.
Identifying from `idle.csv` therefore also sees noisy pressure inputs
(errors-in-variables).

## Checked statistics (noise-free file)

* %(rows)d rows, %(cycles)d cycles, %(dur).4f s;
* mean speed (sample mean over the rows): omega_dw %(mdw).4f rad/s, omega_fw
  %(mfw).4f rad/s; omega_dw in [%(dwlo).3f, %(dwhi).3f] rad/s;
* cycle means of omega_dw: %(cmeans)s rad/s (the slow wander is the cycle-to-cycle
  variation of the heat release, time constant sum J / sum C of about 1.4 s);
  warm-up cycle means: %(wmeans)s;
* speed ripple (peak to peak per cycle): omega_dw %(rip).3f rad/s on average
  (max %(ripmax).3f), omega_fw %(ripfw).3f rad/s;
* max twist wheel-throw 1 %(tw1).3g rad, throw 1-flywheel %(tw2).3g rad.

## Reference residuals (true parameters)

The model output with the true parameters is `omega_dw` of `idle_clean.csv`; the
residual is omega_dw of `idle.csv` minus it, the residual ratio (the methodology paper Fig. 2b)
is residual / omega_dw of `idle.csv`. Max |residual ratio| over all cycles:
%(rmax).5f (the paper reports about 0.006 for its measured data).

| cycle | crank_deg | t [s] | mean omega_dw | p2p omega_dw | p2p omega_fw | peak p_cyl1..4 [bar] | max abs residual ratio | RMSE [rad/s] |
|---|---|---|---|---|---|---|---|---|
%(clines)s

## How strongly each parameter shows in omega_dw

RMS change of omega_dw over recorded cycle 0 when one parameter is raised by 1 %%,
simulated from the exact state at the first row (truth.json
`state_at_first_sample`) with the same pressures:

| parameter | RMS change [rad/s] |
|---|---|
%(slines)s

The couplings' dampings C21, C32, Cxx (and, less so, J1 and J2) barely show in the
damping-wheel speed at idle: far below the %(so)g rad/s noise of `idle.csv`, so
from the noisy file they are practically unidentifiable, and recovering them to 1 %%
from `idle_clean.csv` needs a simulation that reproduces omega_dw to well below
1e-5 rad/s (the speeds are written to about 1e-7 rad/s).

## Regenerate

    python3 scripts/generate_engine_data.py            # writes data/engine/
    python3 scripts/generate_engine_data.py --out DIR  # elsewhere

Python 3 standard library only; the output is deterministic. The run takes about
1.5 minutes on two cores (the half-step check runs in a second process).
""" % kw


if __name__ == "__main__":
    sys.exit(main())
