#!/usr/bin/python3
"""Where the Aalto bench models miss torque_lower: the residual's share of the measured
variance by frequency band, the once-per-revolution line, and the bench's power balance,
for models simulated by tvid beside the black-box FIR of docs/real-bench.md (numpy, and
matplotlib with the Agg backend for --plot).

    tvid simulate configs/aalto_bench_run3.yaml --params results/aalto-bench/params.json -o current.csv
    scripts/aalto_bench_residuals.py --run 3 --model current=current.csv [--model NAME=CSV ...]
                                     [--output torque_lower] [--plot OUT.png] [--power]

- Each --model is the CSV of `tvid simulate` on the run: its last window (run 1: the
  validation window; runs 2 and 3: the whole run). Its fit % and bands are over the
  samples tvid scores, so they add up to tvid's fit %. The FIR is scripts/fir_reference.py's: 300 taps per input from w1
  and prop_torque, fitted on run 1 rows [0, 8999), scored on the rows whose lags are all
  measured (from row 299).
- Bands: the residual's periodogram over the scored samples, as a percentage of the
  measured output's variance there (its sum of squares about its mean). The mean of the
  residual is its own row. With all rows the shares add up to (1 - fit/100)^2 * 100.
- The line: the complex amplitude 2·mean(y·exp(-i·θ1)) of measured and simulated
  torque_lower, and of w1, over the FIR's rows, at order 1 of the motor encoder's angle θ1 = enc1_deg (the
  runs are one continuous rotation, so θ1 has the same zero in all three).
- --power: the mean power through each transducer and into the load motor (through its
  1:8 gear: 8·prop_torque·w5) in 3 s blocks of every run, and the losses between them.
- --plot: the Welch spectra (2048 samples, Hann, half overlap) of the measured output and
  of each residual, 0-120 Hz on a log scale and 48-60 Hz on a linear one.
"""
import argparse
import csv
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import fir_reference  # noqa: E402  (its CSV reader and its lagged regressors)

DATA = os.path.join(HERE, "..", "data", "aalto_bench", "ice_excitation{}.csv")
BANDS = [(0, 15), (15, 20), (20, 50), (50, 56), (56, 150), (150, 500)]   # [a, b) Hz; the last up to 500 Hz
TAPS = 300
DT = 1e-3


def recording(run):
    names, rows = fir_reference.read_recording(DATA.format(run))
    table = np.array(rows)
    return {name: table[:, i] for i, name in enumerate(names)}


def simulated(path, output):
    """(row index, measured, simulated) of an output in the last window of a `tvid simulate` CSV (run 1:
    the validation window, the FIR's rows; runs 2 and 3: the whole run)."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    column = {name.split(" [")[0]: i for i, name in enumerate(header)}
    for key in ("t", "window", f"{output}_measured", f"{output}_simulated"):
        if key not in column:
            sys.exit(f"aalto_bench_residuals.py: {path}: no column {key}")
    # The last window: the rows after the last change of window label or restart of time
    # (the estimation and validation windows of runs 2 and 3 are the same samples).
    t = np.array([float(r[column["t"]]) for r in rows])
    label = [r[column["window"]] for r in rows]
    restarts = [i for i in range(len(rows) - 1) if t[i + 1] <= t[i] or label[i + 1] != label[i]]
    start = restarts[-1] + 1 if len(restarts) else 0
    rows = rows[start:]
    index = np.rint(t[start:] / DT).astype(int)
    measured = np.array([float(r[column[f"{output}_measured"]]) for r in rows])
    model = np.array([float(r[column[f"{output}_simulated"]]) for r in rows])
    return index, measured, model


def fir_prediction(output):
    """The FIR of docs/real-bench.md (w1, prop_torque; fitted on run 1 rows [0, 8999)) as a function of a run."""
    run1 = recording(1)
    inputs = np.c_[run1["w1"], run1["prop_torque"]][:8999]
    phi = fir_reference.lagged(inputs, TAPS)[TAPS - 1:]
    coefficients, *_ = np.linalg.lstsq(phi, run1[output][TAPS - 1:8999], rcond=None)
    return lambda data: fir_reference.lagged(np.c_[data["w1"], data["prop_torque"]], TAPS) @ coefficients


def fit_percent(y, yhat):
    return 100.0 * (1.0 - np.linalg.norm(y - yhat) / np.linalg.norm(y - y.mean()))


def band_shares(y, yhat):
    """The residual's mean, then each band, as % of the measured variance."""
    r = y - yhat
    n = len(r)
    total = np.sum((y - y.mean()) ** 2)
    spectrum = np.abs(np.fft.rfft(r - r.mean())) ** 2 / n
    spectrum[1:] *= 2.0
    if n % 2 == 0:
        spectrum[-1] /= 2.0
    f = np.fft.rfftfreq(n, DT)
    top = BANDS[-1][1]
    return [100.0 * n * r.mean() ** 2 / total] + [
        100.0 * spectrum[(f >= a) & ((f < b) | ((b == top) & (f <= b)))].sum() / total for a, b in BANDS]


def line(x, angle_deg):
    return 2.0 * np.mean(x * np.exp(-1j * np.deg2rad(angle_deg)))


def welch(x, segment=2048):
    x = x - x.mean()
    window = np.hanning(segment)
    parts = [x[k:k + segment] * window for k in range(0, len(x) - segment + 1, segment // 2)]
    power = np.mean([np.abs(np.fft.rfft(p)) ** 2 for p in parts], axis=0) / np.sum(window ** 2) * 2 * DT
    return np.fft.rfftfreq(segment, DT), power


def power_balance():
    print("power balance [W], 3 s blocks; time since the line began turning (enc1 / mean speed)")
    print(f"{'run':>3} {'t [s]':>6} {'into load motor':>16} {'motor-upper':>12} {'upper-lower':>12} "
          f"{'lower-load motor':>17} {'whole line':>11}")
    for run in (1, 2, 3):
        d = recording(run)
        start = d["enc1_deg"][0] / 360.0 / (d["w1"].mean() / (2 * np.pi))
        for k in range(0, len(d["t"]) - 2999, 3000):
            s = slice(k, k + 3000)
            motor = np.mean(d["motor_torque"][s] * d["w1"][s])
            upper = np.mean(d["torque_upper"][s] * d["w2"][s])
            lower = np.mean(d["torque_lower"][s] * d["w5"][s])
            load = np.mean(8.0 * d["prop_torque"][s] * d["w5"][s])
            print(f"{run:>3} {start + k * DT:>6.1f} {load:>16.1f} {motor - upper:>12.1f} {upper - lower:>12.1f} "
                  f"{lower - load:>17.1f} {motor - load:>11.1f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", type=int, choices=(1, 2, 3), default=3)
    parser.add_argument("--model", action="append", default=[], help="NAME=CSV of tvid simulate (repeatable)")
    parser.add_argument("--output", default="torque_lower", choices=("torque_lower", "torque_upper"))
    parser.add_argument("--plot", help="write the spectra to this PNG")
    parser.add_argument("--power", action="store_true", help="print the power balance of the three runs")
    args = parser.parse_args()

    data = recording(args.run)
    first = TAPS - 1 if args.run != 1 else 9000   # run 1: the FIR's validation rows
    rows = np.arange(first, len(data["t"]))
    series = [("FIR (w1, prop_torque)", rows, fir_prediction(args.output)(data)[rows])]
    for spec in args.model:
        name, _, path = spec.partition("=")
        index, measured, model = simulated(path, args.output)
        if not np.allclose(measured, data[args.output][index], atol=1e-6):
            sys.exit(f"aalto_bench_residuals.py: {path}: its measured {args.output} is not run {args.run}'s")
        series.append((name, index, model))

    print(f"run {args.run}, {args.output}: fit %, and the residual's share of the measured variance [%]")
    print(f"{'model':<24} {'samples':>8} {'fit %':>7} {'mean':>6} " + " ".join(f"{f'{a:g}-{b:g} Hz':>10}" for a, b in BANDS))
    for name, index, model in series:
        y = data[args.output][index]
        shares = band_shares(y, model)
        print(f"{name:<24} {len(index):>8} {fit_percent(y, model):>7.2f} " + " ".join(
            f"{s:>{6 if i == 0 else 10}.1f}" for i, s in enumerate(shares)))

    angle = data["enc1_deg"]
    print(f"\nonce per motor revolution ({data['w1'].mean() / (2 * np.pi):.2f} Hz), amplitude and phase against enc1:")
    c = line(data["w1"][rows], angle[rows])
    print(f"  {'w1 (measured)':<24} {abs(c):7.3f} rad/s  {np.angle(c):+6.2f} rad")
    c = line(data[args.output][rows], angle[rows])
    print(f"  {args.output + ' measured':<24} {abs(c):7.3f} N m    {np.angle(c):+6.2f} rad")
    for name, index, model in series:
        keep = index >= first
        c = line(model[keep], angle[index[keep]])
        print(f"  {name:<24} {abs(c):7.3f} N m    {np.angle(c):+6.2f} rad")

    if args.power:
        print()
        power_balance()

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax, zoom) = plt.subplots(1, 2, figsize=(10.0, 4.2), gridspec_kw={"width_ratios": [2.2, 1]})
        f, p = welch(data[args.output][rows])
        top = 1.1 * p[(f >= 48) & (f <= 60)].max()
        for a in (ax, zoom):
            a.plot(f, p, color="black", lw=1.6, label=f"measured {args.output}")
        for name, index, model in series:
            f, p = welch(data[args.output][index] - model)
            for a in (ax, zoom):
                a.plot(f, p, lw=1.2, label=f"residual, {name}")
        for a in (ax, zoom):
            a.axvline(data["w1"].mean() / (2 * np.pi), color="grey", ls=":", lw=1)
            a.set_xlabel("frequency [Hz]")
            a.grid(alpha=0.35)
        ax.set_yscale("log")
        ax.set_xlim(0, 120)
        ax.set_ylabel("PSD [(N m)²/Hz]")
        ax.set_title(f"run {args.run}: {args.output} and the residuals (models fitted on run 1)", fontsize=11)
        ax.legend(fontsize=8)
        zoom.set_xlim(48, 60)
        zoom.set_ylim(0, top)
        zoom.set_title("48-60 Hz, linear (dotted: once per motor rev.)", fontsize=10)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
        print(f"\nwritten: {args.plot}")


if __name__ == "__main__":
    main()
