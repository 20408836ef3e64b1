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
A figure named after an output or a parameter gets a safe file name: '/' and the other
characters a file name cannot hold become '_' (an output `w/motor`: sensitivity_w_motor.png).
Each PNG is written to a temporary file and renamed over its name; a directory, FIFO or
device of that name is not replaced.
Uses Debian's python3-matplotlib with the Agg backend (no display needed). Exit status:
0 done, 2 bad input: one line on stderr naming the file, and the key or column (no figure
for the directory; a missing, damaged, non-UTF-8 or deeply nested file; a value of the
wrong type; a missing column or key; a bad option), 3 matplotlib is not installed.
Every read of a report file goes through report_plots/common.py, which checks it.
"""

import argparse
import importlib
import os
import re
import shutil
import sys
import tempfile

# The figure kinds, in the order they are drawn: adding one is one line here.
MODULES = [
    "fit",          # fit.png: measured vs simulated per window, Q and fit % in the titles
    "residuals",    # residual.png (y − y*, in the output's unit), residual_ratio.png
    "residual_analysis",  # residual_analysis.png: residual autocorrelation, input cross-correlation, 99 % bands
    "history",      # cost_history.png
    "multistart",   # multistart.png: each start's cost, sorted, and the noise floor
    "sensitivity",  # sensitivity_OUTPUT.png, sensitivity_ranking.png
    "profile",      # profile.png
    "spectra",      # spectra.png (Welch densities), orders.png (engine orders)
    "modes",        # a tvid modes directory: modes.png, each mode's shape per node
    "frf",          # a tvid frf directory: frf.png, model against the measured H1
    "batch",        # a batch directory: cross_matrix.png, parameter_spread.png
    "design",       # a tvid design directory: design.png, the inputs, spectra and predicted SEs
]


def fail(message, status=2):
    # One line: a control character (a line break in a name) is shown as \xNN.
    message = re.sub(r"[\x00-\x1f\x7f]", lambda m: f"\\x{ord(m.group()):02x}", str(message))
    print(f"plot_report.py: {message}", file=sys.stderr)
    sys.exit(status)


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, not the usage block
        fail(f"{message} (see --help)")


def main():
    for stream in (sys.stdout, sys.stderr):  # names from a report print as they are
        stream.reconfigure(errors="backslashreplace")
    parser = Parser(description="Draw the figures of a tvid output directory as PNG files.")
    parser.add_argument("report_dir", help="directory written by tvid fit, sensitivity, profile, batch, modes or frf")
    parser.add_argument("-o", "--output", help="output directory (default: REPORT_DIR/plots)")
    parser.add_argument("--sensitivity", metavar="SENS_DIR", help="output directory of tvid sensitivity")
    parser.add_argument("--dpi", type=int, default=100, help="resolution (default 100)")
    args = parser.parse_args()
    if not 10 <= args.dpi <= 1200:
        fail(f"--dpi {args.dpi}: expected 10 to 1200")
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        fail("matplotlib is not installed (Debian: apt-get install python3-matplotlib; run with /usr/bin/python3)", 3)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from report_plots import common

    directories = [args.report_dir]
    if args.sensitivity:
        directories.append(args.sensitivity)
    elif os.path.isfile(os.path.join(args.report_dir, "sensitivity", "sensitivity.json")):
        directories.append(os.path.join(args.report_dir, "sensitivity"))
    for d in directories:
        if not os.path.isdir(d):
            fail(f"{d}: not a directory")
    out_dir = args.output or os.path.join(args.report_dir, "plots")
    if os.path.lexists(out_dir) and not os.path.isdir(out_dir):
        fail(f"{out_dir}: exists and is not a directory (-o names the folder the figures go to)")

    # The figures are drawn into a folder inside OUT_DIR and moved into place once every one
    # is drawn: bad input leaves OUT_DIR as it was.
    existed = os.path.isdir(out_dir)
    written, staging = [], None
    name, d = MODULES[0], directories[0]
    try:
        os.makedirs(out_dir, exist_ok=True)
        staging = tempfile.mkdtemp(prefix=".plot_report.", dir=out_dir)
        drawn = []
        for name in MODULES:
            module = importlib.import_module(f"report_plots.{name}")
            for d in directories:
                drawn += module.draw(d, staging, args.dpi)
        written = common.install(staging, out_dir, drawn)
    except common.ReportError as e:
        fail(str(e))
    except OSError as e:
        fail(f"{e.filename or out_dir}: {e.strerror}")
    except Exception as e:  # noqa: BLE001 -- what the checked reads let through: still one line
        if os.environ.get("TVID_PLOT_TRACEBACK"):
            raise
        what = " ".join(f"{type(e).__name__}: {e}".split())
        fail(f"{d}: cannot draw its {name} figures ({what[:300]}): not a report as tvid writes it? "
             "(TVID_PLOT_TRACEBACK=1 shows where)")
    finally:
        if staging:
            shutil.rmtree(staging, ignore_errors=True)
        if not written and not existed and os.path.isdir(out_dir) and not os.listdir(out_dir):
            os.rmdir(out_dir)
    for path in written:
        print(path)
    if not written:
        fail(f"{args.report_dir}: no figure to draw: summary.json: not found "
             "(nor sensitivity.json, profile.json or batch.csv: is this a tvid output directory?)")


if __name__ == "__main__":
    main()
