#!/usr/bin/python3
"""Draw the figures of a tvid report directory as PNG files.

Usage:
    plot_report.py REPORT_DIR [-o OUT_DIR] [--sensitivity SENS_DIR] [--dpi DPI]

From REPORT_DIR (written by `tvid fit`, see docs/report-format.md):
  fit.png             measured vs simulated output (in its unit), one panel per window and output
                      (estimation windows, then validation windows; the methodology paper Figs. 2a/3a,
                      Yoshida & Takamatsu Fig. 7), with each window's Q-index, fit % and RMSE in its
                      title and the verdict in the figure's
  residual_ratio.png  residual ratio (y - y*)/y in percent per window (the methodology paper Figs. 2b/3b)
  cost_history.png    best cost against iteration and against simulations, log scale
                      (Yoshida & Takamatsu Fig. 6)
From SENS_DIR (written by `tvid sensitivity`, see docs/report-format.md; default
REPORT_DIR/sensitivity when it holds a sensitivity.json):
  sensitivity_OUTPUT.png  p*dy/dp over time, one panel per free parameter
                          (the methodology paper Figs. 4-5); dy/dp for a parameter at 0

From a directory written by `tvid profile` (profile.json and profile.csv) instead:
  profile.png         Δχ² against the parameter's value, the 95 % threshold (χ²₁ = 3.84),
                      the profile interval and the linearised one

The figures go to OUT_DIR (default: REPORT_DIR/plots). Uses Debian's python3-matplotlib
with the Agg backend (no display needed). Exit status: 0 done, 2 bad input (a missing or
malformed file), 3 matplotlib is not installed.
"""

import argparse
import csv
import json
import math
import os
import sys


def fail(message, status=2):
    print(f"plot_report.py: {message}", file=sys.stderr)
    sys.exit(status)


try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import ticker
except ImportError:
    fail("matplotlib is not installed (Debian: apt-get install python3-matplotlib; run with /usr/bin/python3)", 3)


def number(cell):
    """A CSV cell as a float: empty is NaN, 'inf'/'-inf' as written."""
    return float(cell) if cell != "" else math.nan


def read_csv(path):
    if not os.path.isfile(path):
        fail(f"{path}: not found (is this a tvid report directory?)")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        fail(f"{path}: empty file, expected a header line")
    return [bare_name(h) for h in rows[0]], rows[1:]


def bare_name(heading):
    """A column's name without the unit tvid writes after it: 'Tds_measured [N m]' -> 'Tds_measured'."""
    return heading.split(" [", 1)[0]


def percent_columns(path):
    """The columns whose heading gives the unit %."""
    with open(path, newline="") as f:
        header = next(csv.reader(f), [])
    return {bare_name(h) for h in header if h.endswith(" [%]")}


def read_json(path):
    if not os.path.isfile(path):
        fail(f"{path}: not found (is this a tvid report directory?)")
    try:
        with open(path) as f:
            return json.load(f)
    except json.JSONDecodeError as e:
        fail(f"{path}:{e.lineno}: not valid JSON: {e.msg}")


def column(header, name, path):
    if name not in header:
        fail(f"{path}: no column {name}")
    return header.index(name)


def windows_of(header, rows, path):
    """{window label: {column: [values]}} in the order the windows appear."""
    w_col = column(header, "window", path)
    out = {}
    for line, row in enumerate(rows, start=2):
        if len(row) != len(header):
            fail(f"{path}:{line}: {len(row)} cells, the header has {len(header)}")
        try:
            values = [number(c) if i != w_col else c for i, c in enumerate(row)]
        except ValueError:
            fail(f"{path}:{line}: a cell is not a number")
        table = out.setdefault(row[w_col], {h: [] for h in header})
        for h, v in zip(header, values):
            table[h].append(v)
    return out


def outputs_of(header):
    return [h[: -len("_measured")] for h in header if h.endswith("_measured")]


def window_metric(summary, split, label, output, key):
    for w in summary.get(split, {}).get("windows", []):
        if w.get("window") == label:
            return w.get("outputs", {}).get(output, {}).get(key)
    return None


def window_q(summary, split, label, output):
    return window_metric(summary, split, label, output, "q_index_percent")


def unit_of(summary, output):
    """The output's unit as summary.json's cost.outputs names it ('' when not given)."""
    for o in summary.get("cost", {}).get("outputs", []):
        if o.get("name") == output:
            return o.get("unit", "")
    return ""


def labelled(name, unit):
    return f"{name} [{unit}]" if unit else name


def traces(report_dir):
    """[(split, label, {column: values})] for estimation then validation, and the outputs."""
    panels, outputs = [], []
    for split in ("estimation", "validation"):
        path = os.path.join(report_dir, f"{split}.csv")
        header, rows = read_csv(path)
        column(header, "t", path)
        outputs = outputs_of(header) or outputs
        for out in outputs:
            for suffix in ("_measured", "_simulated", "_residual", "_residual_ratio"):
                column(header, out + suffix, path)
        percent = percent_columns(path)
        for label, table in windows_of(header, rows, path).items():
            for out in outputs:  # a report from before the ratio was written in %
                name = out + "_residual_ratio"
                if name not in percent:
                    table[name] = [100.0 * v for v in table[name]]
            panels.append((split, label, table))
    return panels, outputs


def title_of(summary):
    name = summary.get("experiment", "?")
    optimizer = summary.get("optimizer", {}).get("name", "?")
    note = ", interrupted" if summary.get("interrupted") else ""
    return f"{name} ({optimizer}{note})"


def save(fig, out_dir, name, dpi):
    path = os.path.join(out_dir, name)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    print(path)


def plot_fit(panels, outputs, summary, out_dir, dpi):
    rows, cols = len(panels), len(outputs)
    fig, axes = plt.subplots(rows, cols, figsize=(8 * cols, 2.2 * rows + 0.8), squeeze=False)
    for r, (split, label, table) in enumerate(panels):
        for c, out in enumerate(outputs):
            ax = axes[r][c]
            # The simulation drawn over the measurement, in a colour and weight of its own.
            ax.plot(table["t"], table[f"{out}_measured"], color="0.55", lw=0.8, label="measured", zorder=1)
            ax.plot(table["t"], table[f"{out}_simulated"], color="tab:red", lw=1.3, ls="--", label="simulated", zorder=3)
            q = window_q(summary, split, label, out)
            fit = window_metric(summary, split, label, out, "fit_percent")
            rmse = window_metric(summary, split, label, out, "rmse")
            figures = ([f"Q = {q:.2f} %"] if q is not None else []) + ([f"fit = {fit:.1f} %"] if fit is not None else []) \
                + ([f"RMSE = {rmse:.3g} {unit_of(summary, out)}".rstrip()] if rmse is not None else [])
            ax.set_title(f"{split}: {label}   " + "   ".join(figures), fontsize=9)
            ax.set_ylabel(labelled(out, unit_of(summary, out)))
            ax.grid(alpha=0.3)
            if r == 0:
                ax.legend(loc="best", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    verdict = summary.get("verdict", {}).get("summary")
    fig.suptitle(f"{title_of(summary)}: measured vs simulated" + (f"   (verdict: {verdict})" if verdict else ""),
                 fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.35 / fig.get_figheight()))  # room for the figure title
    save(fig, out_dir, "fit.png", dpi)


def plot_residual_ratio(panels, outputs, summary, out_dir, dpi):
    rows, cols = len(panels), len(outputs)
    fig, axes = plt.subplots(rows, cols, figsize=(8 * cols, 1.8 * rows + 0.8), squeeze=False)
    for r, (split, label, table) in enumerate(panels):
        for c, out in enumerate(outputs):
            ax = axes[r][c]
            ratio = table[f"{out}_residual_ratio"]  # [%]; empty where y = 0: NaN, a gap
            ax.plot(table["t"], ratio, color="tab:blue", lw=0.8)
            finite = [abs(v) for v in ratio if math.isfinite(v)]
            peak = max(finite) if finite else math.nan
            ax.set_title(f"{split}: {label}   max |r| = {peak:.3g} %", fontsize=9)
            ax.set_ylabel(f"{out} (y-y*)/y [%]", fontsize=8)
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    fig.suptitle(f"{title_of(summary)}: residual ratio", fontsize=11)
    fig.tight_layout()
    save(fig, out_dir, "residual_ratio.png", dpi)


def plot_cost_history(report_dir, summary, out_dir, dpi):
    path = os.path.join(report_dir, "history.csv")
    header, rows = read_csv(path)
    it, ev, cost = (column(header, n, path) for n in ("iteration", "evaluations", "best_cost"))
    points = []
    for line, row in enumerate(rows, start=2):
        try:
            k, n, e = number(row[it]), number(row[ev]), number(row[cost])
        except (ValueError, IndexError):
            fail(f"{path}:{line}: expected iteration,evaluations,best_cost numbers")
        if math.isfinite(e) and e > 0:  # inf while no candidate has a finite cost
            points.append((k, n, e))
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    kind = summary.get("cost", {}).get("kind", "")
    for ax, index, xlabel in ((axes[0], 0, "iteration"), (axes[1], 1, "simulations")):
        ax.plot([p[index] for p in points], [p[2] for p in points], color="tab:green", lw=1.2, marker=".", ms=3)
        ax.set_yscale("log")
        costs = [p[2] for p in points]
        if costs and max(costs) < 100 * min(costs):  # under two decades: label 2, 3, 5 × 10^k too
            ax.yaxis.set_minor_locator(ticker.LogLocator(subs=(2.0, 3.0, 5.0)))
            plain = ticker.FuncFormatter(lambda v, _: f"{v:.3g}")
            ax.yaxis.set_major_formatter(plain)
            ax.yaxis.set_minor_formatter(plain)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"best cost ({kind})" if kind else "best cost")
        ax.grid(alpha=0.3, which="both")
    fig.suptitle(f"{title_of(summary)}: cost history", fontsize=11)
    fig.tight_layout()
    save(fig, out_dir, "cost_history.png", dpi)


def plot_sensitivity(sens_dir, out_dir, dpi):
    info = read_json(os.path.join(sens_dir, "sensitivity.json"))
    path = os.path.join(sens_dir, "sensitivity.csv")
    header, rows = read_csv(path)
    free = info.get("free_parameters", [])
    value_of = {q["name"]: q["value"] for q in info.get("parameters", [])}
    # p·∂y/∂p is 0 for a parameter at 0: show its ∂y/∂p instead.
    raw = {p: value_of.get(p) == 0 for p in free}
    source = {p: column(header, ("d_" if raw[p] else "s_") + p, path) for p in free}
    w_col, t_col, o_col = (column(header, n, path) for n in ("window", "time", "output"))
    values = {p: {} for p in free}
    for line, row in enumerate(rows, start=2):
        if len(row) != len(header):
            fail(f"{path}:{line}: {len(row)} cells, the header has {len(header)}")
        for p in free:
            series = values[p].setdefault(row[o_col], {}).setdefault(row[w_col], ([], []))
            try:
                series[0].append(number(row[t_col]))
                series[1].append(number(row[source[p]]))
            except ValueError:
                fail(f"{path}:{line}: a cell is not a number")
    if not free:
        fail(f"{path}: no free parameters")
    for out in info.get("outputs", []):
        cols = 2 if len(free) > 3 else 1
        n_rows = math.ceil(len(free) / cols)
        fig, axes = plt.subplots(n_rows, cols, figsize=(6 * cols, 1.9 * n_rows + 0.8), squeeze=False, sharex=True)
        for i, p in enumerate(free):
            ax = axes[i // cols][i % cols]
            for t, s in values[p].get(out, {}).values():  # one line per window
                ax.plot(t, s, color="tab:purple", lw=0.9)
            ax.set_title(f"{p} = {value_of.get(p, math.nan):.4g}", fontsize=9)
            ax.set_ylabel(f"∂{out}/∂{p} (at {p} = 0)" if raw[p] else f"{p}·∂{out}/∂{p}", fontsize=8)
            ax.grid(alpha=0.3)
        for j in range(len(free), n_rows * cols):
            axes[j // cols][j % cols].set_visible(False)
        for c in range(cols):  # the lowest panel of each column carries the time axis
            last = axes[max(i // cols for i in range(len(free)) if i % cols == c)][c]
            last.xaxis.set_tick_params(labelbottom=True)
            last.set_xlabel("t [s]")
        fig.suptitle(f"{info.get('experiment', '?')}: scaled sensitivities p·∂{out}/∂p "
                     f"(change of {out} for a 100 % change of p)", fontsize=11)
        fig.tight_layout()
        save(fig, out_dir, f"sensitivity_{out}.png", dpi)


def plot_profile(profile_dir, out_dir, dpi):
    info = read_json(os.path.join(profile_dir, "profile.json"))
    path = os.path.join(profile_dir, "profile.csv")
    header, rows = read_csv(path)
    name = info.get("parameter", header[0] if header else "?")
    v_col, d_col = column(header, name, path), column(header, "delta_chi2", path)
    points = []
    for line, row in enumerate(rows, start=2):
        try:
            points.append((number(row[v_col]), number(row[d_col])))
        except (ValueError, IndexError):
            fail(f"{path}:{line}: expected numbers in {name} and delta_chi2")
    optimum = info.get("optimum", {}).get("value")
    threshold = info.get("threshold", 3.841)
    fig, ax = plt.subplots(figsize=(7, 4.2))
    finite = [(v, d) for v, d in points if math.isfinite(d)]
    curve = sorted(finite + ([(optimum, 0.0)] if optimum is not None else []))
    ax.plot([v for v, _ in curve], [d for _, d in curve], color="tab:blue", lw=1.5, marker="o", ms=4,
            label="profile: the others refitted")
    if optimum is not None:
        ax.plot([optimum], [0.0], marker="*", ms=12, color="tab:red", ls="none", label=f"optimum {optimum:.5g}")
    ax.axhline(threshold, color="0.3", ls=":", lw=1, label=f"95 % threshold (χ²₁ = {threshold:.2f})")
    interval = info.get("interval95", {})
    for key in ("low", "high"):
        if interval.get(key) is not None:
            ax.axvline(interval[key], color="tab:blue", lw=1, alpha=0.7)
    low, high = interval.get("low"), interval.get("high")
    text = f"profile [{'open' if low is None else f'{low:.5g}'}, {'open' if high is None else f'{high:.5g}'}]"
    linear = info.get("linearised_interval95")
    if linear:
        for x in linear:
            ax.axvline(x, color="tab:orange", ls="--", lw=1)
        ax.plot([], [], color="tab:orange", ls="--", label=f"linearised [{linear[0]:.5g}, {linear[1]:.5g}]")
    ax.plot([], [], color="tab:blue", lw=1, alpha=0.7, label=text)
    unit = info.get("unit")
    ax.set_xlabel(f"{name} [{unit}]" if unit else name)
    ax.set_ylabel("Δχ² = (S − S_min) / s²")
    ax.set_ylim(bottom=min(0.0, min((d for _, d in finite), default=0.0)))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best", framealpha=0.9)
    ax.set_title(f"{info.get('experiment', '?')}: profile likelihood of {name}", fontsize=11)
    fig.tight_layout()
    save(fig, out_dir, "profile.png", dpi)


def main():
    parser = argparse.ArgumentParser(description="Draw the figures of a tvid report directory as PNG files.")
    parser.add_argument("report_dir", help="report directory written by tvid fit (or by tvid profile)")
    parser.add_argument("-o", "--output", help="output directory (default: REPORT_DIR/plots)")
    parser.add_argument("--sensitivity", metavar="SENS_DIR", help="output directory of tvid sensitivity")
    parser.add_argument("--dpi", type=int, default=100, help="resolution (default 100)")
    args = parser.parse_args()
    if not os.path.isdir(args.report_dir):
        fail(f"{args.report_dir}: not a directory")
    if args.sensitivity and not os.path.isdir(args.sensitivity):
        fail(f"{args.sensitivity}: not a directory")
    out_dir = args.output or os.path.join(args.report_dir, "plots")
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as e:
        fail(f"{out_dir}: cannot create: {e.strerror}")

    if os.path.isfile(os.path.join(args.report_dir, "profile.json")) and not os.path.isfile(
            os.path.join(args.report_dir, "summary.json")):
        plot_profile(args.report_dir, out_dir, args.dpi)
        return
    summary = read_json(os.path.join(args.report_dir, "summary.json"))
    panels, outputs = traces(args.report_dir)
    if not panels or not outputs:
        fail(f"{args.report_dir}: estimation.csv and validation.csv hold no samples")
    plot_fit(panels, outputs, summary, out_dir, args.dpi)
    plot_residual_ratio(panels, outputs, summary, out_dir, args.dpi)
    plot_cost_history(args.report_dir, summary, out_dir, args.dpi)
    # `tvid sensitivity` writes to REPORT_DIR/sensitivity by default.
    sens_dir = args.sensitivity
    if not sens_dir and os.path.isfile(os.path.join(args.report_dir, "sensitivity", "sensitivity.json")):
        sens_dir = os.path.join(args.report_dir, "sensitivity")
    if sens_dir:
        plot_sensitivity(sens_dir, out_dir, args.dpi)


if __name__ == "__main__":
    main()
