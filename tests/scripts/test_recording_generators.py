#!/usr/bin/env python3
"""The shipped recordings of the model elements are their generators' output: each
scripts/generate_NAME_data.py, run into a fresh folder, writes data/NAME/ byte for byte.

    test_recording_generators.py SOURCE_DIR WORK_DIR
"""
import filecmp
import os
import shutil
import subprocess
import sys

RECORDINGS = ["dry_friction", "inverse_friction", "road_load", "clutch_damper", "lossy_gear", "positioning_drive",
              "digital_drive",
              "free_line",
              "constant_load"]


def main():
    source, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    failures = []
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
            if not filecmp.cmp(os.path.join(out, f), os.path.join(shipped, f), shallow=False):
                failures.append(f"{name}/{f} differs from its generator's output")
    for f in failures:
        print(f)
    print(f"{len(RECORDINGS)} generators, {len(failures)} differences")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
