#!/usr/bin/python3
"""scripts/fir_reference.py on recordings made from a known FIR: it finds the FIR (fit %
100 on estimation and validation), scores a mean-removed speed with --detrend, reads a
recording as tvid does (a UTF-8 byte-order mark, '#' comment lines, blank lines, quoted
names, CRLF line ends), and answers bad input with exit status 2 and one line naming it,
never a traceback: a missing column, a FILE:FIRST:LAST that is not row numbers, more taps
than the data carry, a --json target that is a directory, a device or a recording (refused
before the fit, nothing written), a cell or file tvid refuses.

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



def run(*args):
    return subprocess.run([script, *args], capture_output=True, text=True)


def refused(args, *expected):
    """Exit status 2, one line on stderr holding each of `expected`, no traceback, no table."""
    r = run(*args)
    assert r.returncode == 2, (args, r.returncode, r.stdout, r.stderr)
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("fir_reference.py: "), (args, r.stderr)
    assert "Traceback" not in r.stderr and r.stdout == "", (args, r.stdout, r.stderr)
    for text in expected:
        assert text in r.stderr, (args, text, r.stderr)


refused(["--inputs", "u1,u3", "--outputs", "y", "--estimation", run1], "no column u3")
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", run1, "--taps", "x"], "--taps", "'x'")
refused(["--inputs", "u1,u2", "--estimation", run1], "--outputs")

# FILE:FIRST:LAST with a window that is not row numbers.
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", f"{run1}:a:b"], f"{run1}:a:b", "FIRST 'a'")
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", run1, "--validation", f"{run2}:10:x"],
        f"{run2}:10:x", "LAST 'x'")
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", f"{run1}:-5:"], "FIRST '-5'")
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", f"{run1}:300:100"], "no samples in rows [300, 100)")

# More taps than samples: refused, not a fit % of nan. Also fewer samples than coefficients,
# and a validation set shorter than the taps.
refused(["--inputs", "u1,u2", "--outputs", "y", "--taps", "5000", "--estimation", run1], run1, "--taps 5000")
refused(["--inputs", "u1,u2", "--outputs", "y", "--taps", "100", "--estimation", f"{run1}:0:150"],
        "201 coefficients")
refused(["--inputs", "u1,u2", "--outputs", "y", "--taps", "50", "--estimation", run1, "--validation", f"{run2}:0:20"],
        f"{run2}:0:20", "--taps 50")
# A FIR whose lagged inputs would not fit in memory: refused before they are built.
big = os.path.join(work_dir, "big.csv")
with open(big, "w") as f:
    f.write("t,u1,y\n" + "".join(f"{i},{i % 7},{i % 3}\n" for i in range(40000)))
refused(["--inputs", "u1", "--outputs", "y", "--taps", "20000", "--estimation", big], "--taps 20000", "GB")

# --json on a directory, a device, a recording or in a missing directory: refused before the fit.
before = sorted(os.listdir(work_dir))
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", run1, "--json", work_dir], f"--json {work_dir}",
        "directory")
assert sorted(os.listdir(work_dir)) == before, "a file was left in the --json directory"
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", run1, "--json", "/dev/null"], "not a regular file")
recorded = open(run2).read()
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", run1, "--validation", run2, "--json", run2],
        f"--json {run2}", "recording")
assert open(run2).read() == recorded, "the recording was overwritten"
refused(["--inputs", "u1,u2", "--outputs", "y", "--estimation", run1, "--json",
         os.path.join(work_dir, "missing", "fir.json")], "no directory")

# A recording as tvid reads it: a UTF-8 byte-order mark, comment and blank lines, quoted
# names, CRLF line ends and a '+' sign give the same fit as the plain file.
lines = open(run1).read().splitlines()
dressed = os.path.join(work_dir, "dressed.csv")
with open(dressed, "w", encoding="utf-8-sig", newline="") as f:
    header = ",".join(f'"{n}"' for n in lines[0].split(","))
    f.write("# bench run 1, 1 kHz\r\n\r\n" + header + "\r\n# units: s, N m, N m\r\n")
    for k, line in enumerate(lines[1:]):
        f.write(("+" + line if k == 7 else line) + ("\r\n\r\n" if k == 100 else "\r\n"))
r = run("--inputs", "u1,u2", "--outputs", "y,w", "--taps", "5", "--estimation", f"{dressed}:0:250",
        "--validation", f"{dressed}:250:", "--json", out_json)
assert r.returncode == 0, r.stderr
for row in json.load(open(out_json))["fit_percent"]:
    assert row["y"] > 99.999 and row["w"] > 99.999, row

# What tvid refuses in a recording, refused with tvid's message and the line.
def bad_recording(name, text, *expected, encoding="utf-8"):
    path = os.path.join(work_dir, name)
    with open(path, "w", encoding=encoding, newline="") as f:
        f.write(text)
    refused(["--inputs", "u1", "--outputs", "y", "--taps", "1", "--estimation", path], path, *expected)


body = "".join(f"{i},{i % 3},{2 * (i % 3)}\n" for i in range(20))
bad_recording("nan.csv", "t,u1,y\n" + body + "20,nan,1\n", ":22: column u1: value is not finite (nan)")
bad_recording("short.csv", "t,u1,y\n" + body + "20,1\n", ":22: column y: short row")
bad_recording("word.csv", "t,u1,y\n" + body + "20,x1,1\n", ":22: column u1: 'x1' is not a number")
bad_recording("huge.csv", "t,u1,y\n" + body + "20,1e400,1\n", ":22: column u1: '1e400' is out of the range")
bad_recording("semicolon.csv", "t;u1;y\n0;1;2\n", ":1: columns are separated by ';'")
bad_recording("utf16.csv", "t,u1,y\n" + body, ":1: file is not text", encoding="utf-16")
bad_recording("comments.csv", "# nothing yet\n\n", ":1: no header row")
bad_recording("binary.csv", "t,u1,y\n0,1,2\n1,\x00,2\n", ":3: file is not text")
bad_recording("twice.csv", "t,u1,u1\n0,1,2\n", "column u1 appears twice")

# A constant output has no fit %: null in the JSON, '-' in the table, not nan.
constant = os.path.join(work_dir, "constant.csv")
with open(constant, "w") as f:
    f.write("t,u1,y\n" + "".join(f"{i},{(i * 7) % 5},4\n" for i in range(50)))
r = run("--inputs", "u1", "--outputs", "y", "--taps", "2", "--estimation", constant, "--json", out_json)
assert r.returncode == 0 and "nan" not in r.stdout, (r.stdout, r.stderr)
assert json.load(open(out_json))["fit_percent"][0]["y"] is None
print("fir_reference.py: recovers a known FIR; --detrend; reads a recording as tvid does; bad input is exit 2, "
      "one line")
