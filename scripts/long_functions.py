#!/usr/bin/env python3
"""Functions in lib/ and apps/ longer than a limit (100 lines by default), each with its
length, name and first line: Universal Ctags gives every C++ function's first and last line
(its `end:` field), so a function's length counts its signature, its body and the lambdas
inside it.

    scripts/long_functions.py [SOURCE_DIR] [--limit 100] [--known FILE]

With --known (tests/layers/long_functions.txt: "LINES NAME FILE" per line), the known long
functions may stay while they do not grow, and the script exits 1 when a function passes
the limit that the file does not list, when a listed one grew, or when a listed one is
now within the limit (then strike it from the file): the list only shrinks.
"""
import argparse
import os
import shutil
import subprocess
import sys


def long_functions(source, limit):
    """[(lines, name, file, first line)] of every function over `limit` lines, longest first."""
    ctags = shutil.which("ctags-universal") or shutil.which("ctags")
    if ctags is None:
        sys.exit("long_functions: Universal Ctags is not installed (scripts/install-deps.sh installs it)")
    run = subprocess.run([ctags, "--fields=+ne", "--kinds-C++=f", "--languages=C++", "--language-force=C++", "-x",
                          "--_xformat=%n|%e|%N|%F", "-R", "lib", "apps"],
                         cwd=source, capture_output=True, text=True, check=True)
    found = []
    for line in run.stdout.splitlines():
        first, last, name, path = line.split("|", 3)
        if not last:
            continue
        lines = int(last) - int(first) + 1
        if lines > limit:
            found.append((lines, name, path, int(first)))
    return sorted(found, key=lambda f: (-f[0], f[2], f[3]))


def read_known(path):
    known = {}
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if line:
                lines, name, file = line.split(None, 2)
                known[(name, file)] = int(lines)
    return known


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("source", nargs="?", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    ap.add_argument("--limit", type=int, default=100)
    ap.add_argument("--known")
    args = ap.parse_args()
    found = long_functions(args.source, args.limit)
    for lines, name, path, first in found:
        print(f"{lines:5d}  {name}  {path}:{first}")
    if not args.known:
        return 0
    known = read_known(args.known)
    problems = []
    seen = set()
    for lines, name, path, first in found:
        key = (name, path)
        seen.add(key)
        if key not in known:
            problems.append(f"{path}:{first}: {name} has {lines} lines, over the limit of {args.limit}: split it")
        elif lines > known[key]:
            problems.append(f"{path}:{first}: {name} grew to {lines} lines from {known[key]} (known long): split it")
    for key, lines in known.items():
        if key not in seen:
            problems.append(f"{key[1]}: {key[0]} is within {args.limit} lines now: strike it from {args.known}")
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
