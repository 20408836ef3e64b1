#!/usr/bin/env bash
# Runs the benchmark cases of docs/performance.md, each in its own process (so the peak
# memory is the case's own) and several times, and prints the median of every figure.
# Figures only: nothing passes or fails on time.
#
# Usage: scripts/bench.sh [--quick] [--repeats N] [--build DIR]
#   default  (a) the paper swarm on 1 and 2 threads through run_fit (what `tvid fit` calls),
#            `tvid fit configs/cvt_tipin.yaml` itself timed end to end, without the stop at the personal best,
#            one candidate at a time instead of SIMD groups, and a swarm of the same size
#            on the non-smooth clearance law (what the rest of a right-hand side costs);
#            the baseline over 25 iterations of the same swarm, (b) the engine LM fit,
#            (c) the batch over every usable engine cycle (cycles 2-7, minutes),
#            (d) window length 1x/4x/16x, 3 repeats
#   --quick  1 repeat (or --repeats N after it), the engine batch over cycles 2-3 only
# The baseline's wall time for the whole swarm is extrapolated from its simulations per
# second (it is one thread, one candidate at a time; its time per simulation is steady).
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build/release"
repeats=3
quick=0
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1; repeats=1 ;;
    --repeats) repeats="$2"; shift ;;
    --build) build="$2"; shift ;;
    *) echo "usage: scripts/bench.sh [--quick] [--repeats N] [--build DIR]" >&2; exit 2 ;;
  esac
  shift
done
bench="$build/bench/tvid_bench"
tvid="$build/apps/tvid/tvid"
results="$(mktemp)"
trap 'rm -f "$results"' EXIT

run() {  # run N LABEL COMMAND...: N repeats of one case, its rows tagged LABEL
  local n="$1" label="$2"; shift 2
  for _ in $(seq "$n"); do
    "$@" | sed -n "s/^case=[^ ]*/case=$label/p" >> "$results"
  done
}

# The engine batch through the command line: wall time and peak memory from GNU time
# (getrusage of the child), simulations from the batch table.
batch() {
  local cycles="$1" out
  out="$(mktemp -d)"
  local stats
  stats="$( { /usr/bin/time -f '%e %M %U' "$tvid" batch "$root/configs/engine_idle.yaml" --cycles "$cycles" \
              -o "$out" --force --quiet > /dev/null; } 2>&1 | tail -1)"
  local sims
  sims="$(python3 -c "import csv,sys; print(sum(int(r['evaluations'] or 0) for r in csv.DictReader(open(sys.argv[1]))))" "$out/batch.csv")"
  local threads
  threads="$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['threads'])" "$out/batch_summary.json")"
  set -- $stats
  echo "case=engine-batch-$cycles wall_s=$1 sims=$sims sims_per_s=$(python3 -c "print($sims/$1)") rhs=0 ns_per_rhs=0 threads=$threads peak_mb=$(python3 -c "print($2/1024)") cpu_s=$3 cpu_ns_per_rhs=0 note=-" >> "$results"
  rm -rf "$out"
}

# The paper's swarm as the user runs it: `tvid fit configs/cvt_tipin.yaml`, the whole
# process (loading, the swarm, scoring the windows, the uncertainty, the report), timed
# from outside; its optimizer time and right-hand sides from summary.json.
fit_e2e() {
  local out stats
  out="$(mktemp -d)"
  stats="$( { /usr/bin/time -f '%e %M %U' "$tvid" fit "$root/configs/cvt_tipin.yaml" -o "$out/r" --threads 2 \
              --quiet > /dev/null; } 2>&1 | tail -1)"
  local fields
  fields="$(python3 -c "
import json, sys
s = json.load(open(sys.argv[1]))
o = s['optimizer']
print(o['evaluations'], o['right_hand_sides'], s['optimizer_time_s'], s['cost']['value'])" "$out/r/summary.json")"
  set -- $stats $fields
  echo "case=tvid-fit-cvt-tipin wall_s=$1 sims=$4 sims_per_s=$(python3 -c "print($4/$1)") rhs=$5" \
       "ns_per_rhs=$(python3 -c "print($1*1e9/$5)") threads=2 peak_mb=$(python3 -c "print($2/1024)") cpu_s=$3" \
       "cpu_ns_per_rhs=$(python3 -c "print($3*1e9/$5)") note=E=$7,optimizer_s=$6" >> "$results"
  rm -rf "$out"
}

"$bench" cvt-check
run "$repeats" cvt-baseline-25it "$bench" cvt-baseline --iterations 25
run "$repeats" cvt-pso "$bench" cvt-pso --threads 2
for _ in $(seq "$repeats"); do fit_e2e; done
run "$repeats" cvt-pso-1thread "$bench" cvt-pso --threads 1
for r in 1 4 16; do run "$repeats" "cvt-window-x$r" "$bench" cvt-window --repeat "$r" --threads 1; done
run "$repeats" cvt-pso-unbounded "$bench" cvt-pso --threads 2 --unbounded
run "$repeats" cvt-pso-scalar "$bench" cvt-pso --threads 2 --scalar
run "$repeats" cvt-pso-nonsmooth "$bench" cvt-pso-nonsmooth --threads 2
if [ "$quick" = 1 ]; then
  run 1 engine-lm "$bench" engine-lm --threads 2
  batch 2-3
else
  run "$repeats" engine-lm "$bench" engine-lm --threads 2
  batch 2-7
fi

python3 - "$results" "$repeats" <<'PY'
import statistics, sys
rows = {}
for line in open(sys.argv[1]):
    f = dict(kv.split("=", 1) for kv in line.split())
    rows.setdefault(f["case"], []).append(f)
med = lambda rs, k: statistics.median(float(r[k]) for r in rs)
print(f"\nmedians of {sys.argv[2]} run(s) per case")
print(f"{'case':<20} {'wall s':>9} {'sims':>8} {'sim/s':>9} {'ns/RHS/cand':>11} {'threads':>7} {'peak MB':>8} "
      f"{'CPU s':>9} {'CPU ns/RHS':>10}  note")
for case, rs in rows.items():
    print(f"{case:<20} {med(rs,'wall_s'):>9.3f} {med(rs,'sims'):>8.0f} {med(rs,'sims_per_s'):>9.0f} "
          f"{med(rs,'ns_per_rhs'):>11.2f} {rs[0]['threads']:>7} {med(rs,'peak_mb'):>8.1f} "
          f"{med(rs,'cpu_s'):>9.2f} {med(rs,'cpu_ns_per_rhs'):>10.2f}  {rs[0]['note']}")
if "cvt-baseline-25it" in rows and "cvt-pso" in rows:
    base = med(rows["cvt-baseline-25it"], "sims_per_s")
    sims = med(rows["cvt-pso"], "sims")
    wall = med(rows["cvt-pso"], "wall_s")
    print(f"\nbaseline for the whole swarm ({sims:.0f} simulations at {base:.0f} sim/s, extrapolated): {sims/base:.2f} s")
    print(f"speed-up of cvt-pso over the baseline: {sims/base/wall:.1f}x")
    if "tvid-fit-cvt-tipin" in rows:
        e2e = rows["tvid-fit-cvt-tipin"]
        optimizer = statistics.median(float(r["note"].split("optimizer_s=")[1]) for r in e2e)
        print(f"tvid fit configs/cvt_tipin.yaml: {med(e2e,'wall_s'):.3f} s for the whole command, of which the "
              f"swarm {optimizer:.3f} s; the cvt-pso case {wall:.3f} s; right-hand sides "
              f"{med(e2e,'rhs'):.0f} (tvid fit) and {med(rows['cvt-pso'],'rhs'):.0f} (cvt-pso)")
    if "cvt-pso-unbounded" in rows:
        saved = 1 - med(rows["cvt-pso"], "rhs") / med(rows["cvt-pso-unbounded"], "rhs")
        print(f"right-hand sides saved by stopping at the personal best: {100*saved:.1f} %")
    base_cpu = med(rows["cvt-baseline-25it"], "cpu_ns_per_rhs") * med(rows["cvt-baseline-25it"], "rhs") / med(rows["cvt-baseline-25it"], "sims")
    print(f"CPU time per simulation, baseline / cvt-pso: {base_cpu * sims / (med(rows['cvt-pso'], 'cpu_s') * 1e9):.2f}x")
    if "cvt-pso-scalar" in rows:
        print(f"speed-up of the SIMD groups over one candidate at a time (same swarm, 2 threads): "
              f"{med(rows['cvt-pso-scalar'],'wall_s')/wall:.2f}x")
    if "cvt-pso-nonsmooth" in rows and "cvt-pso-unbounded" in rows:
        rest = med(rows["cvt-pso-nonsmooth"], "ns_per_rhs")
        whole = med(rows["cvt-pso-unbounded"], "ns_per_rhs")
        print(f"a right-hand side without the smoothed law (cvt-pso-nonsmooth): {rest:.2f} ns; the smoothed law: "
              f"{whole - rest:.2f} ns ({100 * (whole - rest) / whole:.0f} % of cvt-pso-unbounded's {whole:.2f} ns)")
        print(f"2 s of cvt-pso on 2 threads leaves {2 * 2 / med(rows['cvt-pso'], 'rhs') * 1e9:.2f} ns of thread time "
              f"per right-hand side")
    if "cvt-pso-1thread" in rows:
        one = rows["cvt-pso-1thread"]
        print(f"speed-up from 1 to 2 threads: {med(one,'wall_s')/wall:.2f}x wall; parallel efficiency "
              f"(CPU time on 1 thread / CPU time on 2): {med(one,'cpu_s')/med(rows['cvt-pso'],'cpu_s'):.2f}")
PY
