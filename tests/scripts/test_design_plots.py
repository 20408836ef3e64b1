#!/usr/bin/python3
"""scripts/report_plots/design.py on a report that `tvid design --evaluate` writes here (the
constant-load example, a given input beside the three generated ones): design.png drawn, a
report with a candidate's input file cut short refused in one line with exit status 2, and
nothing from a folder without design.json.

    test_design_plots.py SOURCE_DIR TVID WORK_DIR
"""
import os
import shutil
import subprocess
import sys

source_dir, tvid, work_dir = sys.argv[1], sys.argv[2], sys.argv[3]
sys.path.insert(0, os.path.join(source_dir, "scripts"))
from report_plots import design  # noqa: E402

report = os.path.join(work_dir, "report")
shutil.rmtree(work_dir, ignore_errors=True)
subprocess.run([tvid, "design", os.path.join(source_dir, "configs", "constant_load.yaml"), "--evaluate", "--quiet",
                "-o", report, "--input", os.path.join(source_dir, "data", "constant_load", "constant_load.csv"),
                "--set", "design={ input: T_motor, duration: 2.5, band: [0.5, 40], limits: [-20, 40], base: 10, "
                "rms: 8, noise: { w2: 0.05, T_shaft: 0.2 } }"], check=True)

plots = os.path.join(work_dir, "plots")
os.makedirs(plots, exist_ok=True)
written = design.draw(report, plots, 60)
assert written == ["design.png"], written
with open(os.path.join(plots, "design.png"), "rb") as png:
    assert png.read(8) == b"\x89PNG\r\n\x1a\n"
assert os.path.getsize(os.path.join(plots, "design.png")) > 20000

# A candidate's input file without its input column: one line naming the file and column.
with open(os.path.join(report, "chirp.csv"), "w") as f:
    f.write("t,other\n0,1\n")
r = subprocess.run([sys.executable, os.path.join(source_dir, "scripts", "plot_report.py"), report, "-o", plots],
                   capture_output=True, text=True)
assert r.returncode == 2, (r.returncode, r.stderr)
assert r.stderr.count("\n") == 1 and "chirp.csv" in r.stderr and "T_motor" in r.stderr, r.stderr

empty = os.path.join(work_dir, "empty")
os.makedirs(empty, exist_ok=True)
assert design.draw(empty, plots, 60) == []
print("design.py: design.png drawn; a damaged input file refused in one line; nothing from an empty folder")
