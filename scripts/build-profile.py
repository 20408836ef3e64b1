#!/usr/bin/env python3
"""Where a build's time went, from the build directory's .ninja_log.

    scripts/build-profile.py [BUILD_DIR] [--top N] [--phases SOURCE.cpp]

Prints the build's wall time (first start to last end of the newest build in the log),
the compile time summed over all translation units (the CPU time two cores share), the
N slowest translation units, and the compile time per target (library, tool, tests,
benchmarks). With --phases it compiles one source again with the compiler's own timer
(`-ftime-report` with GCC, `-ftime-trace` with clang) and prints its slowest phases:
whether the time is spent parsing headers or generating code.
Standard library only.
"""
import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile


def newest_build(log_path):
    """The entries of the newest build in a .ninja_log (v5): output -> (start_ms, end_ms)."""
    with open(log_path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    if not lines or not lines[0].startswith("# ninja log"):
        sys.exit(f"build-profile: {log_path}: not a ninja log")
    entries = []
    for line in lines[1:]:
        fields = line.split("\t")
        if len(fields) < 4:
            continue
        entries.append((int(fields[0]), int(fields[1]), fields[3]))
    # A new build starts where the start times go back to (near) zero.
    builds = [[]]
    last_start = -1
    for start, end, output in entries:
        if start < last_start and start < 1000:
            builds.append([])
        builds[-1].append((start, end, output))
        last_start = start
    latest = {}
    for start, end, output in builds[-1]:
        latest[output] = (start, end)
    return latest


def target_of(output):
    """The CMake target an object file belongs to ('CMakeFiles/NAME.dir/...')."""
    m = re.search(r"CMakeFiles/([^/]+)\.dir/", output)
    return m.group(1) if m else "(link and other steps)"


def show_phases(build_dir, source):
    with open(os.path.join(build_dir, "compile_commands.json"), encoding="utf-8") as f:
        commands = json.load(f)
    wanted = os.path.abspath(source)
    entry = next((c for c in commands if os.path.abspath(c["file"]) == wanted or c["file"].endswith(source)), None)
    if entry is None:
        sys.exit(f"build-profile: {source} is not compiled in {build_dir}")
    args = shlex.split(entry["command"])
    out_dir = tempfile.mkdtemp(prefix="tvid-phases-")
    # Compile into a scratch file so the build's own objects stay untouched.
    i = args.index("-o")
    args[i + 1] = os.path.join(out_dir, "unit.o")
    clang = "clang" in os.path.basename(args[0])
    args += ["-ftime-trace"] if clang else ["-ftime-report"]
    run = subprocess.run(args, cwd=entry["directory"], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"build-profile: the compile of {source} failed:\n{run.stderr[-2000:]}")
    print(f"phases of {entry['file']}:")
    if clang:
        trace = os.path.join(out_dir, "unit.json")
        with open(trace, encoding="utf-8") as f:
            events = json.load(f)["traceEvents"]
        totals = [(e["dur"] / 1e6, e["name"]) for e in events if e.get("name", "").startswith("Total ")]
        for seconds, name in sorted(totals, reverse=True)[:12]:
            print(f"  {seconds:8.2f} s  {name[6:]}")
    else:
        rows = []
        for line in run.stderr.splitlines():
            m = re.match(r"\s*(.+?)\s*:\s*([\d.]+)\s*\(\s*\d+%\)\s*([\d.]+)\s*\(\s*\d+%\)\s*([\d.]+)", line)
            if m and not m.group(1).startswith("TOTAL"):
                rows.append((float(m.group(4)), m.group(1)))
            elif line.strip().startswith("TOTAL"):
                print(f"  total wall {line.split()[-3] if len(line.split()) > 3 else line}")
        for seconds, name in sorted(rows, reverse=True)[:12]:
            print(f"  {seconds:8.2f} s  {name}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir", nargs="?", default="build/release")
    parser.add_argument("--top", type=int, default=15, help="how many translation units to list")
    parser.add_argument("--phases", metavar="SOURCE", help="compile SOURCE again with the compiler's timer")
    a = parser.parse_args()

    log = os.path.join(a.build_dir, ".ninja_log")
    if not os.path.isfile(log):
        sys.exit(f"build-profile: {log}: no such file (build first)")
    if a.phases:
        show_phases(a.build_dir, a.phases)
        return

    entries = newest_build(log)
    compiles = {o: (s, e) for o, (s, e) in entries.items() if o.endswith(".o")}
    if not entries:
        sys.exit(f"build-profile: {log} holds no build")
    wall = (max(e for _, e in entries.values()) - min(s for s, _ in entries.values())) / 1000
    cpu = sum(e - s for s, e in compiles.values()) / 1000
    print(f"{a.build_dir}: {len(compiles)} compiles, {len(entries) - len(compiles)} other steps")
    print(f"  wall {wall:.1f} s, compile time summed {cpu:.1f} s")

    print(f"\nslowest translation units:")
    for output, (s, e) in sorted(compiles.items(), key=lambda kv: kv[1][0] - kv[1][1])[: a.top]:
        name = re.sub(r"^.*CMakeFiles/[^/]+\.dir/", "", output)
        print(f"  {(e - s) / 1000:7.1f} s  {target_of(output)}: {name.removesuffix('.o')}")

    per_target = {}
    for output, (s, e) in entries.items():
        t = target_of(output)
        count, total = per_target.get(t, (0, 0))
        per_target[t] = (count + output.endswith(".o"), total + e - s)
    print(f"\nper target:")
    for t, (count, total) in sorted(per_target.items(), key=lambda kv: -kv[1][1]):
        print(f"  {total / 1000:7.1f} s  {t} ({count} compiles)")


if __name__ == "__main__":
    main()
