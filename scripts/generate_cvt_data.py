#!/usr/bin/env python3
"""Generate the synthetic CVT tip-in reference data set in data/cvt/.

What it generates
-----------------
A deterministic, synthetic stand-in for the full-scale CVT drivetrain recording of
Yoshida & Takamatsu ("PSO-based Model Identification of a Full-Scale CVT Drivetrain", Fig. 2):
the CVT input shaft torque Ttm(t) and the driveshaft torque Tds(t), sampled every
1 ms from t = 1.000 s to t = 3.500 s inclusive (2501 samples).

* Ttm(t) is a shaped, fully deterministic signal: closed-throttle cruise at
  40 km/h, throttle ramp 0 -> 0.5 from t = 1.540 s to t = 2.033 s (paper Fig. 2),
  a first-order-lag torque rise following the ramp, a decaying low-frequency
  driveline (shuffle) oscillation, and a second-engine-order firing ripple whose
  amplitude grows with load.
* Tds(t) is the output Tds* = F_sigma(theta, theta') + d_ds of the single-DOF
  clearance model of the paper (eqs. 8-11, 15) with the paper's Table I
  parameters, driven by Ttm(t):

      theta''   = rho1 * (Ttm(t) - d_tm - F_sigma(theta, theta'))
      F_sigma   = G_sigma(theta) + H_sigma(theta) * theta'
      G_sigma   = -k_minus * phi1(-theta - mu) + k_plus * phi1(theta - mu)
      H_sigma   =  c_minus * phi2(-theta - mu) + c_plus * phi2(theta - mu)
      phi1(x)   = ln(1 + exp(sigma x)) / sigma     (evaluated overflow-safe)
      phi2(x)   = (1 + tanh(sigma x)) / 2

  Numerical scheme (the one the tvid tool uses, so that a fit on the noise-free
  file can be exact to rounding): classic fixed-step RK4, one step per sample
  interval (step = difference of the time stamps as written), input inside a step
  linearly interpolated between the recorded (written-and-parsed-back) Ttm
  samples (the half-step value is the mean of the two neighbours), initial state
  theta' = 0 and theta = equilibrium G_sigma(theta) = Ttm(t_start) - d_tm solved
  by bisection to full double precision. The output sample at t_i is
  F_sigma(theta(t_i), theta'(t_i)) + d_ds.

Files written (default folder: <repository root>/data/cvt)
---------------------------------------------------------
* tipin_clean.csv  noise-free twin, columns t,Ttm,Tds
* tipin_a.csv      the same recording with Gaussian white measurement noise,
                   std 0.5 N m on Ttm and std 0.5 N m on Tds (independent; the
                   true Tds is computed from the noise-free Ttm, then each
                   recorded channel gets its own noise), columns t,Ttm,Tds
* truth.json       true parameters, noise levels, seed, reference costs
* README.md        description of the data set

Noise: random.Random(SEED) with SEED = 20240601; first all 2501 Ttm noise samples
are drawn with gauss(0, 0.5), then all 2501 Tds noise samples with gauss(0, 0.5).
All numbers are written with '%.10g'. Only the Python 3 standard library is used.

Usage:  python3 scripts/generate_cvt_data.py [--out data/cvt]
"""

import argparse
import json
import math
import os
import random
import sys

# --------------------------------------------------------------------------------------
# Fixed settings
# --------------------------------------------------------------------------------------

SEED = 20240601
NOISE_STD_TTM = 0.5  # N m
NOISE_STD_TDS = 0.5  # N m
DT = 0.001           # s
T_BEGIN = 1.0        # s
T_END = 3.5          # s
N_SAMPLES = 2501     # t_i = 1.0 + i*0.001, i = 0..2500
FMT = "%.10g"
SCRIPT_NAME = "scripts/generate_cvt_data.py"

# Reference-cost window (paper Sec. V-A): [t1, t2] = [1.5, 3]
WINDOW = (1.5, 3.0)

PARAM_NAMES = ["rho1", "k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma", "d_ds", "d_tm"]

# Paper Table I (identified p0 at k = 250), used as the true parameters.
TRUE_PARAMS = {
    "rho1": 1.42855,
    "k_minus": 2947.91,
    "k_plus": 8700.64,
    "c_minus": 4.10333,
    "c_plus": 19.2283,
    "mu": 3.55701e-3,
    "sigma": 1132.81,
    "d_ds": -7.40521,
    "d_tm": 12.9998,
}

# --------------------------------------------------------------------------------------
# Shape of the true input Ttm(t) (all deterministic)
# --------------------------------------------------------------------------------------

THROTTLE_START = 1.540   # s, ramp of the throttle opening ratio a from 0 ...
THROTTLE_END = 2.033     # s, ... to A_MAX (paper Fig. 2)
A_MAX = 0.5
TTM_CRUISE = 11.0        # N m, closed-throttle cruise torque at the CVT input shaft
TTM_LOADED = 90.0        # N m, steady torque at a = 0.5
LAG_TAU = 0.20           # s, first-order lag of the torque build-up behind the throttle
LAG_DELAY = 0.05         # s, transport delay (intake) before the torque reacts

SHUFFLE_START = 1.600    # s, onset of the driveline (shuffle) oscillation
SHUFFLE_AMP = 40.0       # N m, amplitude scale of the oscillation
SHUFFLE_FREQ = 6.0       # Hz
SHUFFLE_RISE = 0.060     # s, rise time constant of the oscillation envelope
SHUFFLE_DECAY = 0.45     # s, decay time constant of the oscillation envelope

RIPPLE_F0 = 55.0         # Hz, second engine order at cruise
RIPPLE_F1 = 68.0         # Hz, second engine order at full load of the ramp (engine speeds up)
RIPPLE_AMP0 = 1.0        # N m, ripple amplitude at closed throttle
RIPPLE_AMP1 = 4.0        # N m, additional ripple amplitude at a = 0.5 (grows with load)


def throttle(t):
    """Throttle opening ratio a(t) of the experiment (0 -> 0.5 ramp)."""
    if t <= THROTTLE_START:
        return 0.0
    if t >= THROTTLE_END:
        return A_MAX
    return A_MAX * (t - THROTTLE_START) / (THROTTLE_END - THROTTLE_START)


def _lagged_ramp(s):
    """Response of tau*x' + x = u to a unit-slope ramp u = s (s >= 0), x(0) = 0."""
    if s <= 0.0:
        return 0.0
    return s - LAG_TAU * (1.0 - math.exp(-s / LAG_TAU))


def load(t):
    """Normalised engine load in [0, 1]: throttle a(t)/A_MAX through a delay and a lag."""
    slope = 1.0 / (THROTTLE_END - THROTTLE_START)
    td = t - LAG_DELAY
    return slope * (_lagged_ramp(td - THROTTLE_START) - _lagged_ramp(td - THROTTLE_END))


def ripple_phase(t):
    """Phase of the second engine order; frequency follows the load (integrated)."""
    # f(t) = F0 + (F1 - F0) * load(t); integrate load analytically via its ramp form.
    slope = 1.0 / (THROTTLE_END - THROTTLE_START)

    def int_lagged_ramp(s):  # integral_0^s of _lagged_ramp
        if s <= 0.0:
            return 0.0
        return 0.5 * s * s - LAG_TAU * s + LAG_TAU * LAG_TAU * (1.0 - math.exp(-s / LAG_TAU))

    td = t - LAG_DELAY
    int_load = slope * (int_lagged_ramp(td - THROTTLE_START) - int_lagged_ramp(td - THROTTLE_END))
    return 2.0 * math.pi * (RIPPLE_F0 * (t - T_BEGIN) + (RIPPLE_F1 - RIPPLE_F0) * int_load)


def shuffle(t):
    """Decaying low-frequency driveline oscillation excited by the tip-in."""
    s = t - SHUFFLE_START
    if s <= 0.0:
        return 0.0
    env = (1.0 - math.exp(-s / SHUFFLE_RISE)) * math.exp(-s / SHUFFLE_DECAY)
    return SHUFFLE_AMP * env * math.sin(2.0 * math.pi * SHUFFLE_FREQ * s)


def ttm_true(t):
    """The noise-free CVT input shaft torque Ttm(t) [N m]."""
    x = load(t)
    base = TTM_CRUISE + (TTM_LOADED - TTM_CRUISE) * x
    rip = (RIPPLE_AMP0 + RIPPLE_AMP1 * x) * math.sin(ripple_phase(t))
    return base + shuffle(t) + rip


# --------------------------------------------------------------------------------------
# The model (Yoshida & Takamatsu eqs. 8-11, 15)
# --------------------------------------------------------------------------------------


def phi1(x, sigma):
    z = sigma * x
    return (max(z, 0.0) + math.log1p(math.exp(-abs(z)))) / sigma


def phi2(x, sigma):
    return 0.5 * (1.0 + math.tanh(sigma * x))


def g_sigma(theta, p):
    mu, sg = p["mu"], p["sigma"]
    return -p["k_minus"] * phi1(-theta - mu, sg) + p["k_plus"] * phi1(theta - mu, sg)


def h_sigma(theta, p):
    mu, sg = p["mu"], p["sigma"]
    return p["c_minus"] * phi2(-theta - mu, sg) + p["c_plus"] * phi2(theta - mu, sg)


def f_sigma(theta, omega, p):
    return g_sigma(theta, p) + h_sigma(theta, p) * omega


def rhs(theta, omega, u, p):
    return omega, p["rho1"] * (u - p["d_tm"] - f_sigma(theta, omega, p))


def equilibrium(target, p):
    """theta with G_sigma(theta) = target, by bisection to full double precision."""
    lo, hi = -1e-3, 1e-3
    while g_sigma(lo, p) > target:
        lo *= 2.0
    while g_sigma(hi, p) < target:
        hi *= 2.0
    while True:
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if g_sigma(mid, p) < target:
            lo = mid
        else:
            hi = mid
    # pick the better of the two bracketing neighbours
    return lo if abs(g_sigma(lo, p) - target) <= abs(g_sigma(hi, p) - target) else hi


def simulate(t, u, p, start, stop):
    """Tds* at samples start..stop (inclusive), started at sample `start` from the
    equilibrium of Ttm(t_start) with theta' = 0. RK4, one step per sample interval,
    input linearly interpolated between samples."""
    theta = equilibrium(u[start] - p["d_tm"], p)
    omega = 0.0
    out = [f_sigma(theta, omega, p) + p["d_ds"]]
    for i in range(start, stop):
        h = t[i + 1] - t[i]
        u0 = u[i]
        u1 = u[i + 1]
        um = 0.5 * (u0 + u1)
        a1, b1 = rhs(theta, omega, u0, p)
        a2, b2 = rhs(theta + 0.5 * h * a1, omega + 0.5 * h * b1, um, p)
        a3, b3 = rhs(theta + 0.5 * h * a2, omega + 0.5 * h * b2, um, p)
        a4, b4 = rhs(theta + h * a3, omega + h * b3, u1, p)
        theta = theta + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
        omega = omega + h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4)
        if not (math.isfinite(theta) and math.isfinite(omega)):
            raise RuntimeError("simulation diverged at t = %g" % t[i + 1])
        out.append(f_sigma(theta, omega, p) + p["d_ds"])
    return out


def roundtrip(x):
    return float(FMT % x)


def reference_cost(t, ttm, tds, p, window):
    """l1 cost E and Q-index over samples with window[0] < t <= window[1], simulation
    started at the sample t = window[0] (Yoshida & Takamatsu eqs. 18-21)."""
    start = min(range(len(t)), key=lambda i: abs(t[i] - window[0]))
    stop = max(i for i in range(len(t)) if t[i] <= window[1])
    sim = simulate(t, ttm, p, start, stop)
    e = 0.0
    e0 = 0.0
    m = 0
    for k, i in enumerate(range(start, stop + 1)):
        if not (window[0] < t[i] <= window[1]):
            continue
        e += abs(sim[k] - tds[i])
        e0 += abs(tds[i] - p["d_ds"])
        m += 1
    e /= m
    e0 /= m
    return {"E": e, "E0": e0, "Q": (1.0 - e / e0) * 100.0, "samples": m,
            "t_start": t[start], "t_end": t[stop]}


# --------------------------------------------------------------------------------------
# Files
# --------------------------------------------------------------------------------------


def write_csv(path, header_lines, t, ttm, tds):
    with open(path, "w", newline="\n") as f:
        for line in header_lines:
            f.write("# " + line + "\n")
        f.write("t,Ttm,Tds\n")
        for a, b, c in zip(t, ttm, tds):
            f.write(FMT % a + "," + FMT % b + "," + FMT % c + "\n")


def read_csv(path):
    t, ttm, tds = [], [], []
    with open(path) as f:
        header = None
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            if header is None:
                header = line.split(",")
                assert header == ["t", "Ttm", "Tds"], header
                continue
            a, b, c = line.split(",")
            t.append(float(a))
            ttm.append(float(b))
            tds.append(float(c))
    return t, ttm, tds


def statistics(t, ttm, tds, p):
    def rng(vals):
        return min(vals), max(vals)

    dwell = [i for i in range(len(t)) if 1.7 <= t[i] <= 2.0 and abs(tds[i] - p["d_ds"]) <= 1.0]
    # group dwell samples into contiguous intervals
    intervals = []
    for i in dwell:
        if intervals and i == intervals[-1][1] + 1:
            intervals[-1][1] = i
        else:
            intervals.append([i, i])
    return {
        "Ttm_range": rng(ttm),
        "Tds_range": rng(tds),
        "Ttm_first": ttm[0],
        "Tds_first": tds[0],
        "Ttm_last_mean": sum(ttm[-200:]) / 200.0,
        "Tds_last_mean": sum(tds[-200:]) / 200.0,
        "dwell_samples_1.7_2.0": len(dwell),
        "dwell_intervals": [(t[a], t[b], b - a + 1) for a, b in intervals],
    }


def main(argv=None):
    repo_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(repo_root, "data", "cvt"),
                    help="output folder (default: <repo>/data/cvt)")
    ap.add_argument("--quiet", action="store_true", help="do not print statistics")
    args = ap.parse_args(argv)
    out = args.out
    os.makedirs(out, exist_ok=True)
    p = dict(TRUE_PARAMS)

    # Time stamps and the noise-free input, as written (round-tripped through FMT).
    t = [roundtrip(T_BEGIN + i * DT) for i in range(N_SAMPLES)]
    ttm = [roundtrip(ttm_true(x)) for x in t]

    # True driveshaft torque: whole recording simulated from the equilibrium at t = 1.0.
    tds = simulate(t, ttm, p, 0, N_SAMPLES - 1)

    # Measurement noise.
    rng = random.Random(SEED)
    n_ttm = [rng.gauss(0.0, NOISE_STD_TTM) for _ in range(N_SAMPLES)]
    n_tds = [rng.gauss(0.0, NOISE_STD_TDS) for _ in range(N_SAMPLES)]
    ttm_noisy = [a + b for a, b in zip(ttm, n_ttm)]
    tds_noisy = [a + b for a, b in zip(tds, n_tds)]

    common = [
        "Units: t in s, Ttm and Tds in N m. Sampling interval 0.001 s, t = 1.000 ... 3.500 s.",
        "Ttm: CVT input shaft torque (synthetic tip-in, throttle ramp 1.540-2.033 s).",
        "Tds: driveshaft torque = output of the 1-DOF clearance model (Yoshida & Takamatsu eq. 15)",
        "     with the paper's Table I parameters (see truth.json), RK4 at 1 ms.",
        "Generated by %s (deterministic, seed %d)." % (SCRIPT_NAME, SEED),
    ]
    clean_path = os.path.join(out, "tipin_clean.csv")
    noisy_path = os.path.join(out, "tipin_a.csv")
    write_csv(clean_path,
              ["CVT tip-in, synthetic reference data: NOISE-FREE twin of tipin_a.csv."]
              + common + ["Noise: none."],
              t, ttm, tds)
    write_csv(noisy_path,
              ["CVT tip-in, synthetic reference data with measurement noise."]
              + common
              + ["Noise: Gaussian white, std %g N m on Ttm and %g N m on Tds (independent);"
                 % (NOISE_STD_TTM, NOISE_STD_TDS),
                 "       true Tds computed from the noise-free Ttm (tipin_clean.csv)."],
              t, ttm_noisy, tds_noisy)

    # Reference costs, recomputed from the files as written (the CSV's own Ttm as input).
    costs = {}
    for label, path in (("noisy", noisy_path), ("clean", clean_path)):
        ft, fttm, ftds = read_csv(path)
        c = reference_cost(ft, fttm, ftds, p, WINDOW)
        costs[label] = {"file": os.path.basename(path), "E": c["E"], "Q": c["Q"],
                        "E0": c["E0"], "samples": c["samples"]}

    truth = {
        "model": "cvt_clearance",
        "parameters": {k: p[k] for k in PARAM_NAMES},
        "noise_std": {"Ttm": NOISE_STD_TTM, "Tds": NOISE_STD_TDS},
        "seed": SEED,
        "sampling_interval": DT,
        "time_span": [T_BEGIN, T_END],
        "files": {"noisy": "tipin_a.csv", "clean": "tipin_clean.csv"},
        "generator": SCRIPT_NAME,
        "reference_costs": {
            "window": list(WINDOW),
            "definition": ("true parameters; scored samples 1.5 < t <= 3.0; simulation "
                           "started at t = 1.5 from the equilibrium of the file's Ttm(1.5) "
                           "with theta' = 0, RK4 one step per sample, input linearly "
                           "interpolated; E = mean |Tds* - Tds|, E0 = mean |Tds - d_ds|, "
                           "Q = (1 - E/E0)*100"),
            "noisy": costs["noisy"],
            "clean": costs["clean"],
        },
    }
    with open(os.path.join(out, "truth.json"), "w", newline="\n") as f:
        json.dump(truth, f, indent=2)
        f.write("\n")

    st = statistics(t, ttm, tds, p)
    with open(os.path.join(out, "README.md"), "w", newline="\n") as f:
        f.write(readme_text(p, costs, st))

    if not args.quiet:
        for k, v in st.items():
            print("%-22s %s" % (k, v))
        for label in ("noisy", "clean"):
            c = costs[label]
            print("%-6s E = %.10g  E0 = %.10g  Q = %.10g  (m = %d)"
                  % (label, c["E"], c["E0"], c["Q"], c["samples"]))
    return 0


def readme_text(p, costs, st):
    plines = "\n".join("| %s | %.10g |" % (k, p[k]) for k in PARAM_NAMES)
    dw = ", ".join("%.3f-%.3f s" % (a, b) for a, b, n in st["dwell_intervals"] if n >= 3)
    return """# CVT clearance model: synthetic tip-in reference data

Synthetic stand-in for the full-scale CVT drivetrain recording of Yoshida & Takamatsu
(Yoshida & Takamatsu, "PSO-based Model Identification of a Full-Scale CVT
Drivetrain", Fig. 2), generated by `scripts/generate_cvt_data.py`. The true
parameters are known, so the identification of the `cvt_clearance` model can be
checked against them.

## Files

| file | content |
|---|---|
| `tipin_clean.csv` | noise-free twin: columns `t,Ttm,Tds` |
| `tipin_a.csv` | the same recording with measurement noise: columns `t,Ttm,Tds` |
| `truth.json` | true parameters, noise levels, seed, reference costs |

Both CSV files start with `#` comment lines, then the header `t,Ttm,Tds`, then
2501 rows: t = 1.000, 1.001, ..., 3.500 s (sampling interval 1 ms). Units: t in s,
Ttm (CVT input shaft torque) and Tds (driveshaft torque) in N m. Numbers are
written with `%%.10g`.

## Model (Yoshida & Takamatsu eqs. 8-11, 15)

    theta''   = rho1 * (Ttm(t) - d_tm - F_sigma(theta, theta'))
    F_sigma   = G_sigma(theta) + H_sigma(theta) * theta'
    G_sigma   = -k_minus * phi1(-theta - mu) + k_plus * phi1(theta - mu)
    H_sigma   =  c_minus * phi2(-theta - mu) + c_plus * phi2(theta - mu)
    phi1(x)   = ln(1 + exp(sigma x)) / sigma      phi2(x) = (1 + tanh(sigma x)) / 2
    Tds*      = F_sigma(theta, theta') + d_ds

Simulation: classic RK4, one step per sample interval, input Ttm linearly
interpolated between the recorded samples (as written in the CSV), initial
state theta' = 0, theta = equilibrium G_sigma(theta) = Ttm(t_start) - d_tm
(bisection to full double precision); output at t_i from the state at t_i.
`Tds` in `tipin_clean.csv` is this simulation run over the whole recording
from t = 1.0 s, driven by the clean file's own `Ttm` column.

## True parameters (paper Table I)

| parameter | value |
|---|---|
%s

## Noise

`tipin_a.csv` = `tipin_clean.csv` plus independent Gaussian white noise,
standard deviation %g N m on Ttm and %g N m on Tds (`random.Random(%d)`,
first all Ttm noise samples, then all Tds noise samples). The true Tds is
computed from the noise-free Ttm; the recorded Ttm then gets its own noise, so
an identification from `tipin_a.csv` sees an input with noise as well
(errors-in-variables).

## How the input Ttm was shaped (deterministic)

* closed-throttle cruise at 40 km/h: Ttm about %g N m (Ttm - d_tm = -2 N m,
  the gear rests lightly against the backward flank, at the edge of the
  clearance; Tds about -9.4 N m);
* throttle ratio a ramps 0 -> 0.5 from t = 1.540 to 2.033 s and holds;
  the torque follows through a %g s delay and a first-order lag (tau = %g s)
  up to %g N m;
* a decaying driveline shuffle oscillation from t = %g s: %g Hz, amplitude
  scale %g N m, envelope rise %g s, decay %g s; it makes Tds swing strongly
  negative and positive and cross the clearance (stationary intervals near
  Tds = d_ds, like the arrows in the paper's Fig. 2);
* second-engine-order firing ripple, %g -> %g Hz with load, amplitude
  %g + %g * load N m.

Checked statistics of the clean data: Ttm in [%.1f, %.1f] N m, Tds in
[%.1f, %.1f] N m; during 1.7 <= t <= 2.0 s, %d samples have |Tds - d_ds| <= 1 N m
(clearance dwell intervals of 3 or more samples: %s).

## Reference costs (true parameters)

Window [1.5, 3.0] s: scored samples 1.5 < t <= 3.0 (m = %d), simulation
restarted at t = 1.5 s from the equilibrium of the file's own Ttm(1.5) with
theta' = 0, input = the file's own Ttm column.
E = mean |Tds* - Tds|, E0 = mean |Tds - d_ds|, Q = (1 - E/E0) * 100.

| file | E [N m] | E0 [N m] | Q [%%] |
|---|---|---|---|
| `tipin_a.csv` (noisy) | %.6g | %.6g | %.6g |
| `tipin_clean.csv` | %.6g | %.6g | %.6g |

The clean-file E is not exactly zero because the simulation restarts at 1.5 s
from an equilibrium while the recording was slightly in motion there (ripple).

## Regenerate

    python3 scripts/generate_cvt_data.py            # writes data/cvt/
    python3 scripts/generate_cvt_data.py --out DIR  # elsewhere

Python 3 standard library only; the output is deterministic.
""" % (plines, NOISE_STD_TTM, NOISE_STD_TDS, SEED,
       TTM_CRUISE, LAG_DELAY, LAG_TAU, TTM_LOADED,
       SHUFFLE_START, SHUFFLE_FREQ, SHUFFLE_AMP, SHUFFLE_RISE, SHUFFLE_DECAY,
       RIPPLE_F0, RIPPLE_F1, RIPPLE_AMP0, RIPPLE_AMP1,
       st["Ttm_range"][0], st["Ttm_range"][1], st["Tds_range"][0], st["Tds_range"][1],
       st["dwell_samples_1.7_2.0"], dw or "none",
       costs["noisy"]["samples"],
       costs["noisy"]["E"], costs["noisy"]["E0"], costs["noisy"]["Q"],
       costs["clean"]["E"], costs["clean"]["E0"], costs["clean"]["Q"])


if __name__ == "__main__":
    sys.exit(main())
