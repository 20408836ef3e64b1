#!/usr/bin/env python3
"""The shipped recordings of the model elements are their generators' output: each
scripts/generate_NAME_data.py, run into a fresh folder, writes the files of data/NAME/.

A CSV recording must have the same header line, the same number of rows and columns, and
every number within RTOL of the shipped one, relative to its column's largest magnitude
(a value near a zero crossing is not judged by its own tiny size). numpy chooses its SIMD
kernels by the processor (SSE, AVX2, AVX-512), and those round differently in the last
bits: an RK4 march over thousands of samples then differs from one machine to another,
by up to 6e-11 of a column's magnitude between an AVX2 and an AVX-512 machine (8.8e-8 of
a value near zero).
Every other file (the truth.json beside each recording) is compared byte for byte.

    test_recording_generators.py SOURCE_DIR WORK_DIR
"""
import filecmp
import os
import shutil
import subprocess
import sys

RECORDINGS = ["dry_friction", "inverse_friction", "road_load", "clutch_damper", "lossy_gear", "positioning_drive",
              "digital_drive", "rigid_gear", "driveline",
              "free_line",
              "constant_load"]

# 12 significant digits are written; machines differ by up to 6e-11 of a column's magnitude.
RTOL = 1e-9


def read_csv(path):
    with open(path) as f:
        lines = f.read().splitlines()
    return lines[0], [line.split(",") for line in lines[1:]]


def compare_csv(written, shipped):
    """None when the two recordings agree within RTOL, else the first difference in words."""
    header_w, rows_w = read_csv(written)
    header_s, rows_s = read_csv(shipped)
    if header_w != header_s:
        return f"header '{header_w}' against '{header_s}'"
    if len(rows_w) != len(rows_s):
        return f"{len(rows_w)} rows against {len(rows_s)}"
    columns = len(rows_s[0]) if rows_s else 0
    values_s = [[float(v) for v in row] for row in rows_s]
    scale = [max(abs(row[c]) for row in values_s) for c in range(columns)]
    for i, (row_w, row_s) in enumerate(zip(rows_w, values_s)):
        if len(row_w) != columns:
            return f"row {i + 2}: {len(row_w)} columns against {columns}"
        for c, (text, b) in enumerate(zip(row_w, row_s)):
            try:
                a = float(text)
            except ValueError:
                return f"row {i + 2}, column {c + 1}: '{text}' is not a number"
            relative = abs(a - b) / max(scale[c], 1e-300)
            if relative > RTOL:
                return f"row {i + 2}, column '{header_s.split(',')[c]}': {a!r} against {b!r} ({relative:.2g} of the column's magnitude)"
    return None


def main():
    source, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    failures = []
    inexact_files = 0
    for name in RECORDINGS:
        out = os.path.join(work, name)
        subprocess.run([sys.executable, os.path.join(source, "scripts", f"generate_{name}_data.py"), out],
                       check=True, stdout=subprocess.DEVNULL)
        shipped = os.path.join(source, "data", name)
        files = sorted(os.listdir(shipped))
        if sorted(os.listdir(out)) != files:
            failures.append(f"{name}: wrote {sorted(os.listdir(out))}, data/{name} has {files}")
            continue
        for f in files:
            written, reference = os.path.join(out, f), os.path.join(shipped, f)
            if f.endswith(".csv"):
                difference = compare_csv(written, reference)
                if difference is not None:
                    failures.append(f"{name}/{f} differs from its generator's output: {difference}")
                elif not filecmp.cmp(written, reference, shallow=False):
                    inexact_files += 1
            elif not filecmp.cmp(written, reference, shallow=False):
                failures.append(f"{name}/{f} differs from its generator's output")
    for f in failures:
        print(f)
    print(f"{len(RECORDINGS)} generators, {len(failures)} differences beyond {RTOL:g} of a column's magnitude "
          f"({inexact_files} CSV files equal within it but not byte for byte)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
