#!/usr/bin/env bash
# Batch-fits every usable cycle of the shipped engine idle recording on its own and prints
# how much the identified parameters spread from cycle to cycle.
#
# data/engine/idle.csv holds complete cycles 0 … 8 (crank angle 0 … 7199.5 deg). Each
# estimation cycle needs the experiment's 2-cycle warm-up before it and is validated on
# the next cycle, so cycles 2 … 7 are usable.
#
# Usage: scripts/batch_engine_cycles.sh [TVID] [extra tvid batch options, e.g. --threads 2]
# Writes results/engine-idle-batch/ (batch.csv, batch_summary.json).
# Under MPI (docs/mpi.md), with the MPI build and the launcher in MPIRUN:
#   MPIRUN='mpirun -q -n 2' scripts/batch_engine_cycles.sh build/mpi/apps/tvid/tvid --threads 1
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
tvid="${1:-$root/build/release/apps/tvid/tvid}"
shift || true
out="$root/results/engine-idle-batch"

# --force: a fresh batch each time (use --resume instead to continue an interrupted one).
# Exit status 1 means some cycle failed; the table and summary are written anyway.
status=0
read -r -a launcher <<< "${MPIRUN:-}"
"${launcher[@]}" "$tvid" batch "$root/configs/engine_idle.yaml" --cycles 2-7 -o "$out" --force "$@" || status=$?
if [ "$status" -ge 2 ]; then exit "$status"; fi

python3 - "$out/batch_summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
processes = f" x {s['processes']} processes" if s.get("processes", 1) > 1 else ""
print(f"\n{s['ok']} of {s['jobs']} cycles fitted, {s['jobs_per_second'] or 0:.3f} cycles/s on {s['threads']} thread(s){processes}")
print(f"{'parameter':<10} {'mean':>12} {'std':>12} {'std/mean':>9} {'min':>12} {'max':>12}")
for name, p in s["parameters"].items():
    if not p["count"]:
        continue
    std = p["std"] if p["std"] is not None else float("nan")
    rel = abs(std / p["mean"]) * 100 if p["mean"] else float("nan")
    print(f"{name:<10} {p['mean']:12.5g} {std:12.3g} {rel:8.1f}% {p['min']:12.5g} {p['max']:12.5g}")
PY
exit "$status"
