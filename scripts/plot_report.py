#!/usr/bin/python3
"""Draw the figures of a tvid output directory as PNG files.

Usage:
    plot_report.py DIR [-o OUT_DIR] [--sensitivity SENS_DIR] [--dpi DPI]

Every figure module below is run on DIR (and on SENS_DIR); each draws what the directory
holds for it and nothing otherwise, so DIR may be written by `tvid fit`, `tvid
sensitivity`, `tvid profile`, `tvid batch`, `tvid modes` or `tvid frf`. The modules live in scripts/report_plots/
(one figure kind each, `draw(directory, out_dir, dpi) -> [PNG names]`); docs/gallery.md
shows every figure with the command that produced it. A fit report's sensitivity run in
DIR/sensitivity (the default of `tvid sensitivity`) is drawn too.

The figures go to OUT_DIR (default: DIR/plots), and their paths are printed one a line.
Uses Debian's python3-matplotlib with the Agg backend (no display needed). Exit status:
0 done, 2 bad input (no figure for the directory, or a missing or malformed file),
3 matplotlib is not installed.
"""

import argparse
import importlib
import os
import sys

# The figure kinds, in the order they are drawn: adding one is one line here.
MODULES = [
    "fit",          # fit.png: measured vs simulated per window, Q and fit % in the titles
    "residuals",    # residual.png (y − y*, in the output's unit), residual_ratio.png
    "history",      # cost_history.png
    "multistart",   # multistart.png: each start's cost, sorted, and the noise floor
    "sensitivity",  # sensitivity_OUTPUT.png, sensitivity_ranking.png
    "profile",      # profile.png
    "spectra",      # spectra.png (Welch densities), orders.png (engine orders)
    "modes",        # a tvid modes directory: modes.png, each mode's shape per node
    "frf",          # a tvid frf directory: frf.png, model against the measured H1
    "batch",        # a batch directory: cross_matrix.png, parameter_spread.png
]


def fail(message, status=2):
    print(f"plot_report.py: {message}", file=sys.stderr)
    sys.exit(status)


def main():
    parser = argparse.ArgumentParser(description="Draw the figures of a tvid output directory as PNG files.")
    parser.add_argument("report_dir", help="directory written by tvid fit, sensitivity, profile, batch, modes or frf")
    parser.add_argument("-o", "--output", help="output directory (default: REPORT_DIR/plots)")
    parser.add_argument("--sensitivity", metavar="SENS_DIR", help="output directory of tvid sensitivity")
    parser.add_argument("--dpi", type=int, default=100, help="resolution (default 100)")
    args = parser.parse_args()
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        fail("matplotlib is not installed (Debian: apt-get install python3-matplotlib; run with /usr/bin/python3)", 3)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from report_plots.common import ReportError

    directories = [args.report_dir]
    if args.sensitivity:
        directories.append(args.sensitivity)
    elif os.path.isfile(os.path.join(args.report_dir, "sensitivity", "sensitivity.json")):
        directories.append(os.path.join(args.report_dir, "sensitivity"))
    for d in directories:
        if not os.path.isdir(d):
            fail(f"{d}: not a directory")
    out_dir = args.output or os.path.join(args.report_dir, "plots")

    written = []
    existed = os.path.isdir(out_dir)
    try:
        for name in MODULES:
            module = importlib.import_module(f"report_plots.{name}")
            for d in directories:
                if not written:  # created once there is something to draw
                    os.makedirs(out_dir, exist_ok=True)
                for png in module.draw(d, out_dir, args.dpi):
                    path = os.path.join(out_dir, png)
                    written.append(path)
                    print(path)
    except ReportError as e:
        fail(str(e))
    except OSError as e:
        fail(f"{e.filename or out_dir}: {e.strerror}")
    if not written:
        if not existed and os.path.isdir(out_dir) and not os.listdir(out_dir):
            os.rmdir(out_dir)
        fail(f"{args.report_dir}: no figure to draw: summary.json: not found "
             "(nor sensitivity.json, profile.json or batch.csv: is this a tvid output directory?)")


if __name__ == "__main__":
    main()
