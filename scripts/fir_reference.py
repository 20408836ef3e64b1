#!/usr/bin/python3
"""The black-box reference for a measured bench: a causal FIR from the input columns to
each output column, fitted by linear least squares on the estimation samples, and its
fit % on the estimation and validation samples and on other recordings.

Usage:
    fir_reference.py --inputs motor_torque,prop_torque --outputs torque_upper,torque_lower
                     --estimation RUN1.csv:0:9000 [--validation RUN1.csv:9000:] [--validation RUN2.csv]
                     [--taps 300] [--detrend] [--json OUT.json]

Each recording is a CSV file with a header row (as tvid reads it); FILE:FIRST:LAST picks
the samples [FIRST, LAST) (either may be empty: the start or the end). The model of
output y is

    y(i) = c + sum_{k=0}^{taps-1} sum_j h_j(k) u_j(i - k)

(each input's last `taps` samples, and a constant), fitted by linear least squares. The FIR is fitted on, and scored over, the samples whose
lags are all measured (a set from a file's first sample leaves out its first taps - 1
samples; a set later in a file sees the inputs before it). The fit % is tvid's:
100 (1 - |y - yhat| / |y - mean(y)|). With
--detrend the mean of y is removed before the fit % in each scored set (a model of
the speed's fluctuation only).

The inputs the FIR sees should be the ones the gray-box model sees: the two motor
torques, or the measured motor speed and the load torque.

Exit status: 0 done, 2 bad input (a missing file or column). Uses numpy only.
"""
import argparse
import csv
import json
import sys

import numpy as np


def fail(message):
    print(f"fir_reference.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_columns(path, names):
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    if not rows:
        fail(f"{path}: empty file")
    header = rows[0]
    missing = [n for n in names if n not in header]
    if missing:
        fail(f"{path}: no column {', '.join(missing)} (columns: {', '.join(header)})")
    data = np.array([[float(r[header.index(n)]) for n in names] for r in rows[1:] if r], dtype=float)
    return data


def parse_set(text):
    parts = text.split(":")
    path = parts[0]
    first = int(parts[1]) if len(parts) > 1 and parts[1] else 0
    last = int(parts[2]) if len(parts) > 2 and parts[2] else None
    return path, first, last


def lagged(u, taps):
    """The regressor matrix [u_j(i - k)] for every sample i, the lags before the first
    sample held at the first sample's value, and a column of ones."""
    n, m = u.shape
    padded = np.vstack([np.repeat(u[:1], taps - 1, axis=0), u])
    columns = [np.ones((n, 1))]
    for j in range(m):
        # Column k holds u_j(i - k).
        windows = np.lib.stride_tricks.sliding_window_view(padded[:, j], taps)[:, ::-1]
        columns.append(windows)
    return np.hstack(columns)


def fit_percent(y, yhat, detrend):
    if detrend:
        y = y - y.mean()
        yhat = yhat - yhat.mean()
    spread = np.linalg.norm(y - y.mean())
    return float(100.0 * (1.0 - np.linalg.norm(y - yhat) / spread)) if spread > 0 else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--inputs", required=True, help="input columns, comma-separated")
    parser.add_argument("--outputs", required=True, help="output columns, comma-separated")
    parser.add_argument("--estimation", required=True, help="FILE[:FIRST[:LAST]]")
    parser.add_argument("--validation", action="append", default=[], help="FILE[:FIRST[:LAST]] (repeatable)")
    parser.add_argument("--taps", type=int, default=300)
    parser.add_argument("--detrend", action="store_true", help="remove each scored set's mean before the fit %%")
    parser.add_argument("--json", help="also write the table as JSON to this file")
    args = parser.parse_args()

    inputs = [c for c in args.inputs.split(",") if c]
    outputs = [c for c in args.outputs.split(",") if c]
    if not inputs or not outputs:
        fail("give at least one input and one output column")
    if args.taps < 1:
        fail("--taps must be at least 1")

    def load(spec):
        path, first, last = parse_set(spec)
        data = read_columns(path, inputs + outputs)
        last = len(data) if last is None else min(last, len(data))
        if not 0 <= first < last:
            fail(f"{spec}: no samples in [{first}, {last})")
        phi = lagged(data[:, : len(inputs)], args.taps)
        return phi[first:last], data[first:last, len(inputs):], first

    def measured_lags(first):
        """The samples of a set from which every lag is a measured sample of its file."""
        return slice(max(0, args.taps - 1 - first), None)

    phi, y, first = load(args.estimation)
    usable = measured_lags(first)
    coefficients, *_ = np.linalg.lstsq(phi[usable], y[usable], rcond=None)

    table = []
    for name, spec in [("estimation", args.estimation)] + [("validation", v) for v in args.validation]:
        phi_s, y_s, first_s = load(spec)
        scored = measured_lags(first_s)
        yhat = phi_s @ coefficients
        row = {"set": name, "data": spec}
        for k, out in enumerate(outputs):
            row[out] = fit_percent(y_s[scored, k], yhat[scored, k], args.detrend)
        table.append(row)

    print(f"causal FIR, {args.taps} taps per input, inputs {', '.join(inputs)}"
          + (" (fit % after mean removal)" if args.detrend else ""))
    print(f"{'set':<11} {'data':<40} " + " ".join(f"{o:>14}" for o in outputs))
    for row in table:
        print(f"{row['set']:<11} {row['data']:<40} " + " ".join(f"{row[o]:>14.1f}" for o in outputs))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"taps": args.taps, "inputs": inputs, "outputs": outputs, "detrend": args.detrend,
                       "fit_percent": table}, f, indent=2)


if __name__ == "__main__":
    main()
