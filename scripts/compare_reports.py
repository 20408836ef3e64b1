#!/usr/bin/python3
"""Do two tvid binaries write the same reports? For every experiment in configs/*.yaml,
each binary runs

    tvid fit      configs/X.yaml --output-dir OUT/X/SIDE/fit
    tvid simulate configs/X.yaml --params OUT/X/SIDE/fit/params.json --output-dir OUT/X/SIDE/simulate
    tvid validate configs/X.yaml --params OUT/X/SIDE/fit/params.json --output-dir OUT/X/SIDE/validate

(SIDE is base or new; simulate and validate read the params.json that the same binary's fit
wrote), from the repository root that holds the configs directory, since the configs name
their recordings relative to themselves (data: file: ../data/...) and summary.json records
the experiment path as given. Every file each command writes (dot files too), and its
stdout and stderr (kept as CMD.stdout, CMD.stderr), is compared with the other binary's
byte for byte (filecmp, shallow=False) after the normalisation below. It prints one row per
config and command: the files compared, the ones that differ, both exit statuses; then, per
differing file, which JSON fields or CSV columns differ and a short diff. Exit status 0 when
every file of every run is identical and the exit statuses agree, 1 otherwise (a timeout
counts as a difference), 2 on bad arguments.

    /usr/bin/python3 scripts/compare_reports.py BASE_TVID NEW_TVID [--configs DIR] [--out DIR]
        [--only GLOB] [--jobs 1|2] [--threads N] [--timeout 600] [--raw]

--only GLOB picks configs by file name (e.g. 'cvt_*' or 'rigid_gear.yaml'; repeatable).
--jobs N runs N tvid processes at a time (at most 2); --threads N is passed to every tvid
command (default: none, tvid's own default of all cores; give the same to both binaries,
since summary.json records it). --timeout S stops a run after S seconds (SIGTERM, then
SIGKILL 15 s later) and reports it as "timeout": its files, which hold wherever it stopped,
are not compared, and the row is not identical; the commands after a fit that timed out or
wrote no params.json are skipped (after a timeout that too is "not identical").
--out DIR keeps the runs (default: a new directory under /tmp); DIR/CONFIG/{base,new} and
DIR/diffs/ (each differing file's full normalised diff) are replaced or written, nothing
else in DIR is touched.
--raw compares without any normalisation: run it with the SAME binary as BASE_TVID and
NEW_TVID to see what differs between two runs of one binary.

What is normalised, and why. These are exactly what differed between two runs of the same
binary (8cb6fdb's tvid against itself, --raw, --threads 1, twice) on constant_load,
cvt_tipin (the swarm), rigid_gear_noisy_input (a declared input noise) and aalto_bench_runs
(three recordings), with every other byte identical, plus the binary's own path (the same
four, normalised and on tvid's default thread count, then came out identical):

  * The run's output directory and the binary's path: summary.json's "command" is the
    command line (argv[0] and the --output-dir/--params paths), and the terminal says
    "report: DIR" or "written: DIR/simulation.csv". In every text file the absolute path
    of the side's own directory (OUT/X/base or OUT/X/new) becomes <OUT> and the binary's
    path as given on the command line becomes <TVID>. Nothing else in "command" is touched.
  * JSON wall-clock fields, whose values change from run to run: "wall_time_s",
    "optimizer_time_s", "evaluations_per_second" (evaluations over the optimizer's wall
    time) get the value "<normalised>" in place (a textual substitution of the value, so
    every other byte, number formatting included, is still compared as written). The
    binary's version ("version", "0.1.0" in both binaries here; tvid embeds no commit or
    date) is treated the same way, as the one field that may legitimately name the binary.
  * The terminal's fit line "..., 0.52 s on 2 threads" and sensitivity's "... s on N
    thread(s)": the seconds become <T>; the thread count stays.
  * stderr's swarm note "tvid: pso: scoring the N particles ... will take at most about
    ..." is printed only when the first iteration predicts a minute or more, so whether
    it is there depends on the machine's load: the line is dropped (it never appeared in
    the runs above; the rule comes from fit_command.cpp).
  * .tvid.lock, the output directory's lock, holds the writer's process id: its content
    becomes <pid>.

Nothing is skipped: a file present on one side only is a difference, and CSV files
(estimation.csv, validation.csv, history.csv, spectra.csv, params.csv, simulation.csv, ...)
are compared as written, none of them held a time or a path in the runs above.
"""
import argparse
import concurrent.futures
import csv
import difflib
import fnmatch
import filecmp
import io
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

COMMANDS = ("fit", "simulate", "validate")
SIDES = ("base", "new")
# JSON keys whose values are wall-clock measurements or the binary's identity.
NORMALISED_JSON_KEYS = ("wall_time_s", "optimizer_time_s", "evaluations_per_second", "version")
_JSON_VALUE = r'(?:-?[0-9][0-9.eE+-]*|null|true|false|"(?:[^"\\]|\\.)*")'
JSON_KEY_RE = re.compile(r'("(?:%s)"\s*:\s*)%s' % ("|".join(NORMALISED_JSON_KEYS), _JSON_VALUE))
TERMINAL_SECONDS_RE = re.compile(r"\b[0-9]+(?:\.[0-9]+)? s on ([0-9]+ threads?)\b")
SWARM_NOTE_RE = re.compile(r"^tvid: [a-z+]+: scoring the .*$\n?", re.MULTILINE)
MAX_DIFF_LINES = 12
MAX_LINE_CHARS = 160


def normalise(text, name, side_dir, tvid):
    """The text of one output file with the fields that differ between equal runs replaced."""
    if name == ".tvid.lock":
        return "<pid>"
    text = text.replace(side_dir, "<OUT>").replace(tvid, "<TVID>")
    if name.endswith(".json") or name.endswith(".stdout"):  # fit/simulate/validate --json print JSON too
        text = JSON_KEY_RE.sub(r'\1"<normalised>"', text)
    if name.endswith(".stdout") or name.endswith(".stderr"):
        text = TERMINAL_SECONDS_RE.sub(r"<T> s on \1", text)
        text = SWARM_NOTE_RE.sub("", text)
    return text


def read_text(path):
    with open(path, "rb") as f:
        return f.read().decode("utf-8", errors="surrogateescape")


class Run:
    """One tvid command of one binary: its exit status, time and files."""

    def __init__(self, status, seconds, files, note=""):
        self.status = status  # int exit status, "timeout", or "skipped"
        self.seconds = seconds
        self.files = files  # {relative name: absolute path}
        self.note = note


def run_tvid(argv, cwd, stdout_path, stderr_path, timeout):
    """(exit status or "timeout", seconds). The process runs in its own session so that a
    timeout stops it and anything it started."""
    t0 = time.monotonic()
    with open(stdout_path, "wb") as out, open(stderr_path, "wb") as err:
        proc = subprocess.Popen(argv, cwd=cwd, stdout=out, stderr=err, stdin=subprocess.DEVNULL,
                                start_new_session=True)
        try:
            status = proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGTERM)
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
            status = "timeout"
    return status, time.monotonic() - t0


def files_under(directory):
    found = {}
    if os.path.isdir(directory):
        for root, _, names in os.walk(directory):
            for n in names:
                full = os.path.join(root, n)
                found[os.path.relpath(full, directory)] = full
    return found


def run_side(tvid, config_rel, root, side_dir, threads, timeout):
    """fit, simulate, validate of one config with one binary: {command: Run}."""
    if os.path.exists(side_dir):
        shutil.rmtree(side_dir)
    os.makedirs(side_dir)
    extra = ["--threads", str(threads)] if threads is not None else []
    params = os.path.join(side_dir, "fit", "params.json")
    runs = {}
    for cmd in COMMANDS:
        out_dir = os.path.join(side_dir, cmd)
        argv = [tvid, cmd, config_rel, "--output-dir", out_dir] + extra
        if cmd != "fit":
            fit = runs["fit"]
            if fit.status == "timeout" or not os.path.isfile(params):
                why = "fit timed out" if fit.status == "timeout" else "the fit wrote no params.json"
                runs[cmd] = Run("skipped", 0.0, {}, why)
                continue
            argv[3:3] = ["--params", params]
        stdout_path = os.path.join(side_dir, cmd + ".stdout")
        stderr_path = os.path.join(side_dir, cmd + ".stderr")
        status, seconds = run_tvid(argv, root, stdout_path, stderr_path, timeout)
        files = {"(" + k + ")": v for k, v in ((cmd + ".stdout", stdout_path), (cmd + ".stderr", stderr_path))}
        files.update(files_under(out_dir))
        runs[cmd] = Run(status, seconds, files)
    return runs


def json_leaves(value, path=""):
    """{path: leaf as text} of a JSON document parsed with numbers kept as written."""
    leaves = {}
    if isinstance(value, dict):
        for k, v in value.items():
            leaves.update(json_leaves(v, path + "." + k if path else k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            leaves.update(json_leaves(v, "%s[%d]" % (path, i)))
    else:
        leaves[path] = value if isinstance(value, str) else json.dumps(value)
    return leaves


def describe_json(a, b):
    try:
        la = json_leaves(json.loads(a, parse_float=str, parse_int=str))
        lb = json_leaves(json.loads(b, parse_float=str, parse_int=str))
    except ValueError:
        return []
    keys = sorted(set(la) | set(lb))
    changed = [k for k in keys if la.get(k) != lb.get(k)]
    lines = ["%d JSON field(s) differ:" % len(changed)]
    for k in changed[:MAX_DIFF_LINES]:
        lines.append("  %s: %s -> %s" % (k, la.get(k, "(absent)"), lb.get(k, "(absent)")))
    if len(changed) > MAX_DIFF_LINES:
        lines.append("  ... and %d more" % (len(changed) - MAX_DIFF_LINES))
    return lines


def describe_csv(a, b):
    ra = list(csv.reader(io.StringIO(a)))
    rb = list(csv.reader(io.StringIO(b)))
    if not ra or not rb:
        return []
    lines = []
    if ra[0] != rb[0]:
        lines.append("header: %s -> %s" % (",".join(ra[0]), ",".join(rb[0])))
    if len(ra) != len(rb):
        lines.append("rows: %d -> %d" % (len(ra) - 1, len(rb) - 1))
    header = ra[0]
    per_column = {}
    for row_a, row_b in zip(ra[1:], rb[1:]):
        for j in range(max(len(row_a), len(row_b))):
            va = row_a[j] if j < len(row_a) else None
            vb = row_b[j] if j < len(row_b) else None
            if va != vb:
                name = header[j] if j < len(header) else "#%d" % j
                count, worst = per_column.get(name, (0, 0.0))
                try:
                    d = abs(float(va) - float(vb))
                except (TypeError, ValueError):
                    d = float("nan")
                per_column[name] = (count + 1, max(worst, d) if d == d else worst)
    for name, (count, worst) in per_column.items():
        lines.append("column %s: %d of %d rows differ, max |diff| %.3g" % (name, count, len(ra) - 1, worst))
    return lines


def short_diff(a, b, name):
    lines = list(difflib.unified_diff(a.splitlines(), b.splitlines(), "base/" + name, "new/" + name, n=0,
                                      lineterm=""))
    shown = [l if len(l) <= MAX_LINE_CHARS else l[:MAX_LINE_CHARS] + " ..." for l in lines[:MAX_DIFF_LINES]]
    if len(lines) > MAX_DIFF_LINES:
        shown.append("... (%d diff lines in all)" % len(lines))
    return shown


def compare_command(cfg, cmd, base, new, sides, tvids, raw, diff_dir):
    """One table row and the details of each differing file."""
    names = sorted(set(base.files) | set(new.files))
    differing, details = [], []
    timed_out = "timeout" in (base.status, new.status)
    for name in ([] if timed_out else names):  # a stopped run's files hold wherever it stopped
        pa, pb = base.files.get(name), new.files.get(name)
        if pa is None or pb is None:
            differing.append(name)
            details.append((name, ["only in " + ("new" if pa is None else "base")]))
            continue
        if filecmp.cmp(pa, pb, shallow=False):
            continue
        if raw:
            ta, tb = read_text(pa), read_text(pb)
        else:
            short = name.strip("()")
            ta = normalise(read_text(pa), os.path.basename(short), sides[0], tvids[0])
            tb = normalise(read_text(pb), os.path.basename(short), sides[1], tvids[1])
            if ta == tb:
                continue
        differing.append(name)
        lines = []
        if name.endswith(".json"):
            lines += describe_json(ta, tb)
        elif name.endswith(".csv"):
            lines += describe_csv(ta, tb)
        lines += short_diff(ta, tb, name)
        full = os.path.join(diff_dir, "%s.%s.%s.diff" % (cfg, cmd, name.strip("()").replace(os.sep, "_")))
        with open(full, "w", encoding="utf-8", errors="surrogateescape") as f:
            f.write("\n".join(difflib.unified_diff(ta.splitlines(), tb.splitlines(), "base/" + name, "new/" + name,
                                                   lineterm="")) + "\n")
        lines.append("(full diff: %s)" % full)
        details.append((name, lines))
    notes = sorted({r.note for r in (base, new) if r.note})
    if timed_out:
        notes.append("timed out, files not compared")
    # Both skipped after fits that wrote no params.json agree; skipped after a timeout, nothing was shown.
    identical = not differing and base.status == new.status and not timed_out and "fit timed out" not in notes
    notes = "; ".join(notes)
    row = {"config": cfg, "command": cmd, "files": len(names), "differing": differing,
           "base": base.status, "new": new.status, "seconds": (base.seconds, new.seconds),
           "identical": identical, "note": notes}
    return row, details


def print_table(rows):
    head = ("config", "command", "files", "differing", "exit base", "exit new", "s base", "s new")
    table = [head]
    for r in rows:
        diff = ", ".join(r["differing"]) if r["differing"] else ("-" if r["identical"] or r["note"] else "(exit status)")
        if r["note"]:
            diff += " [" + r["note"] + "]"
        table.append((r["config"], r["command"], str(r["files"]), diff, str(r["base"]), str(r["new"]),
                      "%.1f" % r["seconds"][0], "%.1f" % r["seconds"][1]))
    widths = [max(len(t[i]) for t in table) for i in range(len(head))]
    for i, t in enumerate(table):
        print("  ".join(c.ljust(w) for c, w in zip(t, widths)).rstrip())
        if i == 0:
            print("  ".join("-" * w for w in widths))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("base_tvid")
    ap.add_argument("new_tvid")
    ap.add_argument("--configs", default=os.path.join(os.path.dirname(here), "configs"),
                    help="directory of the experiments (default: the repository's configs/); the runs start in its parent")
    ap.add_argument("--out", help="where the runs are kept (default: a new directory under /tmp)")
    ap.add_argument("--only", action="append", metavar="GLOB", help="configs whose file name matches (repeatable)")
    ap.add_argument("--jobs", type=int, default=1, help="tvid processes at a time, 1 or 2 (default 1)")
    ap.add_argument("--threads", type=int, help="--threads for every tvid command (default: tvid's own)")
    ap.add_argument("--timeout", type=float, default=600, help="seconds per tvid run (default 600)")
    ap.add_argument("--raw", action="store_true", help="compare without normalisation (to find what differs between runs)")
    args = ap.parse_args()

    if not 1 <= args.jobs <= 2:
        ap.error("--jobs must be 1 or 2 (at most 2 tvid processes run at a time)")
    tvids = [os.path.abspath(t) if os.sep in t else t for t in (args.base_tvid, args.new_tvid)]
    for t in tvids:
        if not (os.path.isfile(t) and os.access(t, os.X_OK)):
            ap.error("not an executable: " + t)
    configs_dir = os.path.abspath(args.configs)
    root = os.path.dirname(configs_dir)
    names = sorted(n for n in os.listdir(configs_dir) if n.endswith(".yaml"))
    if args.only:
        names = [n for n in names if any(fnmatch.fnmatch(n, g) for g in args.only)]
    if not names:
        ap.error("no configs/*.yaml matched")
    out = os.path.abspath(args.out) if args.out else tempfile.mkdtemp(prefix="compare_reports-")
    diff_dir = os.path.join(out, "diffs")
    os.makedirs(diff_dir, exist_ok=True)
    config_rel = {n: os.path.relpath(os.path.join(configs_dir, n), root) for n in names}

    t0 = time.monotonic()
    print("compare_reports: %d configs, base %s, new %s, runs in %s, from %s, %d job(s), timeout %g s%s"
          % (len(names), tvids[0], tvids[1], out, root, args.jobs, args.timeout, ", raw" if args.raw else ""),
          flush=True)
    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {}
        for n in names:
            for side, tvid in zip(SIDES, tvids):
                side_dir = os.path.join(out, n[:-5], side)
                futures[pool.submit(run_side, tvid, config_rel[n], root, side_dir, args.threads, args.timeout)] = (n, side)
        for fut in concurrent.futures.as_completed(futures):
            n, side = futures[fut]
            results[(n, side)] = fut.result()
            r = results[(n, side)]
            print("  done %-34s %-4s %s (%.0f s so far)" % (n, side, " ".join(
                "%s=%s" % (c, r[c].status) for c in COMMANDS), time.monotonic() - t0), flush=True)

    rows, all_details = [], []
    for n in names:
        cfg = n[:-5]
        sides = [os.path.join(out, cfg, s) for s in SIDES]
        for cmd in COMMANDS:
            row, details = compare_command(cfg, cmd, results[(n, "base")][cmd], results[(n, "new")][cmd], sides,
                                           tvids, args.raw, diff_dir)
            rows.append(row)
            all_details += [(cfg, cmd, name, lines) for name, lines in details]
    print()
    print_table(rows)
    if all_details:
        print("\ndifferences (normalised%s):" % (", raw" if args.raw else ""))
        for cfg, cmd, name, lines in all_details:
            print("\n%s %s %s" % (cfg, cmd, name))
            for l in lines:
                print("    " + l)
    bad = [r for r in rows if not r["identical"]]
    unchecked = [r for r in bad if "timed out" in r["note"]]
    timeouts = sum(1 for r in rows for s in ("base", "new") if r[s] == "timeout")
    print("\ncompare_reports: %d of %d runs identical, %d differ, %d not compared after %d timeout(s); %.0f s in all"
          % (len(rows) - len(bad), len(rows), len(bad) - len(unchecked), len(unchecked), timeouts,
             time.monotonic() - t0))
    return 0 if not bad else 1


if __name__ == "__main__":
    sys.exit(main())
