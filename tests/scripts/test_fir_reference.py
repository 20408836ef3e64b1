#!/usr/bin/python3
"""scripts/fir_reference.py on recordings made from a known FIR: it finds the FIR (fit %
100 on estimation and validation), scores a mean-removed speed with --detrend, and
answers a missing column with exit status 2 and one line.

    test_fir_reference.py SOURCE_DIR WORK_DIR
"""
import json
import os
import subprocess
import sys

import numpy as np

source_dir, work_dir = sys.argv[1], sys.argv[2]
os.makedirs(work_dir, exist_ok=True)
script = os.path.join(source_dir, "scripts", "fir_reference.py")
rng = np.random.default_rng(3)


def recording(path, n):
    u1, u2 = rng.normal(size=n), rng.normal(size=n)
    # y = 1 + 2 u1(i) − 0.5 u1(i−2) + 0.25 u2(i−1); the lags before the first sample are
    # the first sample (as the script holds them).
    lag = lambda u, k: np.concatenate([np.full(k, u[0]), u[:-k]])
    y = 1 + 2 * u1 - 0.5 * lag(u1, 2) + 0.25 * lag(u2, 1)
    speed = 300 + y  # a speed with a large mean
    with open(path, "w") as f:
        f.write("t,u1,u2,y,w\n")
        for i in range(n):
            f.write(f"{i * 1e-3},{u1[i]!r},{u2[i]!r},{y[i]!r},{speed[i]!r}\n")


run1, run2 = os.path.join(work_dir, "run1.csv"), os.path.join(work_dir, "run2.csv")
recording(run1, 400)
recording(run2, 300)
out_json = os.path.join(work_dir, "fir.json")
r = subprocess.run([script, "--inputs", "u1,u2", "--outputs", "y,w", "--taps", "5", "--estimation", f"{run1}:0:250",
                    "--validation", f"{run1}:250:", "--validation", run2, "--json", out_json],
                   capture_output=True, text=True)
assert r.returncode == 0, r.stderr
table = json.load(open(out_json))["fit_percent"]
assert [row["set"] for row in table] == ["estimation", "validation", "validation"], table
for row in table:
    assert row["y"] > 99.999, row  # the FIR it was made from
    assert row["w"] > 99.999, row  # the same plus a constant

# --detrend: the same fit on the fluctuation alone; a wrong FIR (too few taps to reach lag 2) is worse.
r = subprocess.run([script, "--inputs", "u1,u2", "--outputs", "w", "--taps", "2", "--detrend", "--estimation",
                    f"{run1}:0:250", "--validation", run2, "--json", out_json], capture_output=True, text=True)
assert r.returncode == 0, r.stderr
short = json.load(open(out_json))["fit_percent"]
assert all(50 < row["w"] < 99 for row in short), short

r = subprocess.run([script, "--inputs", "u1,u3", "--outputs", "y", "--estimation", run1], capture_output=True, text=True)
assert r.returncode == 2, r.returncode
assert r.stderr.count("\n") == 1 and "no column u3" in r.stderr, r.stderr
print("fir_reference.py: recovers a known FIR; --detrend; a missing column is exit 2")
