#!/usr/bin/env python3
"""The library's folders are floors, and an #include may only point down (or within its own
folder): the model knows nothing of how it is simulated, the simulation nothing of the
experiment file, the solvers nothing of models. Prints every include that points up or
sideways, and exits 1 if there is one.

    tests/layers/check_layers.py [SOURCE_DIR]

docs/architecture.md draws the same floors.
"""
import os
import re
import sys

# Lowest first. A file may include its own folder and any folder on a lower floor.
FLOORS = [
    ["util", "simd"],                 # language-level helpers, SIMD packs
    ["io", "channels", "optim"],      # files and tables; measured channels; the solvers
    ["model", "parallel", "check"],   # the network's equations; processes; `tvid check`
    ["sim"],                          # integration of the equations over samples
    ["experiment"],                   # the experiment file, read and checked
    ["estimation"],                   # costs, residuals and sensitivities of an experiment
    ["analysis", "design"],           # what is judged at an optimum; what a record would determine
    ["fit"],                          # one identification run
    ["report", "batch"],              # report files; many fits
    ["api"],                          # the public API (tvid/tvid.hpp) over all of it
]
FLOOR_OF = {folder: level for level, folders in enumerate(FLOORS) for folder in folders}
INCLUDE = re.compile(r'^\s*#\s*include\s+"tvid/([a-z_]+)/([^"]+)"', re.MULTILINE)


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
    lib = os.path.join(root, "lib", "tvid")
    problems = []
    checked = 0
    for folder in sorted(os.listdir(lib)):
        path = os.path.join(lib, folder)
        if not os.path.isdir(path):
            continue
        if folder not in FLOOR_OF:
            problems.append(f"lib/tvid/{folder}/: a folder on no floor (add it to FLOORS and to docs/architecture.md)")
            continue
        # The folder's files and those of its subfolders (fit/optimizers/, model/elements/).
        sources = sorted(os.path.relpath(os.path.join(d, n), path)
                         for d, _, names in os.walk(path) for n in names if n.endswith((".hpp", ".cpp")))
        for name in sources:
            with open(os.path.join(path, name), encoding="utf-8") as f:
                text = f.read()
            for m in INCLUDE.finditer(text):
                checked += 1
                target = m.group(1)
                if target == folder:
                    continue
                if target not in FLOOR_OF:
                    problems.append(f"lib/tvid/{folder}/{name}: includes tvid/{target}/{m.group(2)}, a folder on no floor")
                elif FLOOR_OF[target] >= FLOOR_OF[folder]:
                    way = "up" if FLOOR_OF[target] > FLOOR_OF[folder] else "sideways"
                    problems.append(f"lib/tvid/{folder}/{name}: includes tvid/{target}/{m.group(2)}, "
                                    f"{way} from floor {FLOOR_OF[folder]} ({folder}) to floor {FLOOR_OF[target]} ({target})")
    for p in problems:
        print(p)
    print(f"layers: {checked} includes checked, {len(problems)} against the floors")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
