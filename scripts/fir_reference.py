#!/usr/bin/python3
"""The black-box reference for a measured bench: a causal FIR from the input columns to
each output column, fitted by linear least squares on the estimation samples, and its
fit % on the estimation and validation samples and on other recordings.

Usage:
    fir_reference.py --inputs motor_torque,prop_torque --outputs torque_upper,torque_lower
                     --estimation RUN1.csv:0:9000 [--validation RUN1.csv:9000:] [--validation RUN2.csv]
                     [--taps 300] [--detrend] [--json OUT.json]

Each recording is a CSV file read by tvid's rules (lib/tvid/io/csv_table.cpp): a header
row of column names, then one row of numbers per sample; blank lines and lines starting
with '#' are skipped, a UTF-8 byte-order mark is ignored, cells may be quoted, and a file
that tvid refuses (binary or UTF-16, ';' or tab separated, a short or long row, an empty
or non-finite cell) is refused with tvid's message. FILE:FIRST:LAST picks the data rows
[FIRST, LAST) (either may be empty: the start or the end; a FILE that exists as given
is taken whole, so its name may hold ':'). The model of output y is

    y(i) = c + sum_{k=0}^{taps-1} sum_j h_j(k) u_j(i - k)

(each input's last `taps` samples, and a constant), fitted by linear least squares. The FIR is fitted on, and scored over, the samples whose
lags are all measured (a set from a file's first sample leaves out its first taps - 1
samples; a set later in a file sees the inputs before it). The estimation set must hold
more such samples than the FIR has coefficients (1 + taps per input). The fit % is tvid's:
100 (1 - |y - yhat| / |y - mean(y)|), none (JSON null) for a constant y. With
--detrend the mean of y is removed before the fit % in each scored set (a model of
the speed's fluctuation only).

The inputs the FIR sees should be the ones the gray-box model sees: the two motor
torques, or the measured motor speed and the load torque.

Exit status: 0 done, 2 bad input (one line on stderr: a missing file or column, a file
tvid would refuse, a bad FILE:FIRST:LAST, more taps than the data carry (or than 2 GB
of lagged inputs hold), a --json target that is not a writable file or is one of the
recordings); nothing is written then. The
JSON file is written whole or not at all (a temporary file renamed over it). Uses numpy
only.
"""
import argparse
import json
import math
import os
import re
import stat
import sys
import tempfile

import numpy as np

MAX_RECORDING_BYTES = 1 << 30  # tvid's limit for a recording (lib/tvid/io/input_file.hpp)
MAX_REGRESSOR_BYTES = 2 << 30  # the lagged inputs of one set; the least squares needs about twice that


class BadInput(Exception):
    """Bad input: one line, exit status 2."""


def fail(message):
    # One line: a control character (a line break in a name) is shown as \xNN.
    message = re.sub(r"[\x00-\x1f\x7f]", lambda m: f"\\x{ord(m.group()):02x}", str(message))
    print(f"fir_reference.py: {message}", file=sys.stderr)
    sys.exit(2)


# ---- tvid's CSV reader (lib/tvid/io/csv_table.cpp), the same rules and messages ----------

_BLANKS = " \t\v\f\r"
# What std::from_chars reads as a number, after tvid drops one leading '+'.
_NUMBER = re.compile(r"-?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NOT_FINITE = re.compile(r"-?(?:inf(?:inity)?|nan(?:\([0-9A-Za-z_]*\))?)", re.IGNORECASE)


def _shown(text):
    return text if len(text) <= 40 else text[:40] + "..."


def _lines(text):
    """(line number, line) of a text: lines end at \\n, \\r\\n or a lone \\r."""
    return enumerate(re.split(r"\r\n|\n|\r", text), start=1)


def _unquote(cell):
    return cell[1:-1].strip(_BLANKS) if len(cell) >= 2 and cell[0] == '"' and cell[-1] == '"' else cell


def _number(cell):
    """(value, None) or (None, what is wrong) for a trimmed, unquoted, non-empty cell."""
    body = cell[1:] if len(cell) > 1 and cell[0] == "+" and cell[1] not in "+-" else cell
    if _NUMBER.fullmatch(body):
        value = float(body)
        if math.isinf(value):
            return None, f"'{_shown(cell)}' is out of the range of a double"
        return value, None
    if _NOT_FINITE.fullmatch(body) or any(s in cell.lower() for s in ("#inf", "#ind", "#qnan", "#snan")):
        return None, f"value is not finite ({_shown(cell)})"
    return None, f"'{_shown(cell)}' is not a number"


def _separator(sep):
    return ("columns are separated by ';'" if sep == ";" else "columns are separated by tabs") + \
        " — tvid reads comma-separated files (',' between columns, '.' as decimal point)"


def read_recording(path):
    """(column names, rows as lists of floats) of a recording, read as tvid reads it;
    BadInput naming the file and line otherwise."""
    try:
        st = os.stat(path)
    except OSError as e:
        raise BadInput(f"{path}: " + ("no such data file" if e.errno in (2, 20) else f"cannot open: {e.strerror}"))
    if stat.S_ISDIR(st.st_mode):
        raise BadInput(f"{path}: the data file is a directory, not a file")
    if not stat.S_ISREG(st.st_mode):
        raise BadInput(f"{path}: the data file is not a regular file")
    if st.st_size > MAX_RECORDING_BYTES:
        raise BadInput(f"{path}: the data file is larger than 1 GiB")
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_RECORDING_BYTES + 1)
    except OSError as e:
        raise BadInput(f"{path}: cannot read the data file: {e.strerror}")
    if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
        raise BadInput(f"{path}:1: file is not text (binary data at line 1): it looks UTF-16 encoded — "
                       "save it as UTF-8 or ASCII")
    if data[:3] == b"\xef\xbb\xbf":
        data = data[3:]
    text = data.decode("utf-8", errors="surrogateescape")
    binary = re.search(r"[\x00-\x08\x0e-\x1f]", text)
    if binary:
        line = len(re.findall(r"\r\n|\n|\r", text[:binary.start()])) + 1
        raise BadInput(f"{path}:{line}: file is not text (binary data at line {line})")

    names, header_line, saw_comment, rows = None, 0, False, []
    for number, raw in _lines(text):
        line = raw.strip(_BLANKS)
        if not line or line[0] == "#":
            saw_comment = saw_comment or bool(line)
            continue
        where = f"{path}:{number}"
        if names is None:
            header_line = number
            if "," not in line and (";" in line or "\t" in line):
                raise BadInput(f"{where}: " + _separator(";" if line.count(";") >= line.count("\t") else "\t"))
            names = []
            for index, cell in enumerate(line.split(","), start=1):
                raw_name = cell.strip(_BLANKS)
                name = _unquote(raw_name)
                if not name:
                    raise BadInput(f"{where}: column {index}: empty column name")
                if len(name) == len(raw_name) and (raw_name[0] == '"' or raw_name[-1] == '"'):
                    raise BadInput(f"{where}: column {index}: unbalanced double quote in column name "
                                   f"{_shown(raw_name)}")
                if name in names:
                    raise BadInput(f"{where}: column {name} appears twice (columns {names.index(name) + 1} and {index})")
                names.append(name)
            if all(_number(n)[0] is not None for n in names):
                raise BadInput(f"{where}: no header row: the first row holds numbers ({_shown(line)}), but it must "
                               "name the columns, e.g. time,speed")
            continue
        if ";" in line:
            raise BadInput(f"{where}: " + _separator(";"))
        cells = line.split(",")
        if len(cells) < len(names):
            raise BadInput(f"{where}: column {names[len(cells)]}: short row: {len(cells)} value"
                           f"{'s' if len(cells) != 1 else ''}, header has {len(names)} column"
                           f"{'s' if len(names) != 1 else ''}")
        if len(cells) > len(names):
            raise BadInput(f"{where}: long row: {len(cells)} values, header has {len(names)} column"
                           f"{'s' if len(names) != 1 else ''}")
        row = []
        for name, cell in zip(names, cells):
            cell = _unquote(cell.strip(_BLANKS))
            if not cell:
                raise BadInput(f"{where}: column {name}: empty cell")
            value, wrong = _number(cell)
            if wrong:
                if "\t" in cell:
                    raise BadInput(f"{where}: " + _separator("\t"))
                if wrong.endswith("is not a number") and cell == name:
                    wrong += " (a repeated header row?)"
                elif wrong.endswith("is not a number") and " " in cell:
                    wrong += " (columns must be separated by ',')"
                raise BadInput(f"{where}: column {name}: {wrong}")
            row.append(value)
        rows.append(row)
    if names is None:
        raise BadInput(f"{path}:1: " + ("no header row: the file holds only comments and blank lines" if saw_comment
                                        else "file is empty (expected a header row of column names, then one row "
                                             "per sample)"))
    if not rows:
        raise BadInput(f"{path}:{header_line}: no data rows after the header")
    return names, rows


def read_columns(path, names):
    """The named columns of a recording as an array (rows × names)."""
    header, rows = read_recording(path)
    missing = [n for n in names if n not in header]
    if missing:
        raise BadInput(f"{path}: no column {', '.join(missing)} (columns: {', '.join(header)})")
    index = [header.index(n) for n in names]
    return np.array([[row[i] for i in index] for row in rows], dtype=float).reshape(len(rows), len(names))


def parse_set(text):
    """(path, first, last) of FILE[:FIRST[:LAST]]; last is None for the end."""
    if os.path.exists(text):
        return text, 0, None
    parts = text.split(":")
    if len(parts) > 3:
        raise BadInput(f"{text}: expected FILE[:FIRST[:LAST]] (a file name holding ':' must exist as given)")
    path, bounds = parts[0], []
    for what, cell in zip(("FIRST", "LAST"), parts[1:]):
        if cell and not re.fullmatch(r"[0-9]+", cell.strip()):
            raise BadInput(f"{text}: {what} '{_shown(cell)}' is not a row number (a whole number from 0; "
                           "FILE:FIRST:LAST picks the rows [FIRST, LAST))")
        bounds.append(int(cell) if cell.strip() else None)
    first = bounds[0] if bounds and bounds[0] is not None else 0
    last = bounds[1] if len(bounds) > 1 else None
    if not path:
        raise BadInput(f"{text}: no file name (expected FILE[:FIRST[:LAST]])")
    return path, first, last


def check_json_target(path, recordings):
    """Refuses a --json target that cannot be written as a regular file, or that is one of
    the recordings, before anything is fitted."""
    if os.path.isdir(path) or path.endswith(os.sep):
        raise BadInput(f"--json {path}: is a directory (give a file name, e.g. {os.path.join(path, 'fir.json')})")
    if os.path.lexists(path):
        st = os.stat(path) if os.path.exists(path) else None
        if st is None or not stat.S_ISREG(st.st_mode):
            raise BadInput(f"--json {path}: exists and is not a regular file (it is not replaced)")
        for recording in recordings:
            if os.path.exists(recording) and os.path.samefile(path, recording):
                raise BadInput(f"--json {path}: is the recording {recording} (it would be overwritten)")
    parent = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(parent):
        raise BadInput(f"--json {path}: no directory {parent}")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise BadInput(f"--json {path}: cannot write in {parent}")


def write_json(path, document):
    """Writes the document whole, or not at all: a temporary file beside it, renamed over it."""
    parent = os.path.dirname(os.path.abspath(path))
    fd, temporary = tempfile.mkstemp(prefix=".fir_reference.", suffix=".tmp", dir=parent)
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(document, f, indent=2, allow_nan=False)
            f.write("\n")
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


def lagged(u, taps):
    """The regressor matrix [u_j(i - k)] for every sample i, the lags before the first
    sample held at the first sample's value, and a column of ones."""
    n, m = u.shape
    padded = np.vstack([np.repeat(u[:1], taps - 1, axis=0), u])
    columns = [np.ones((n, 1))]
    for j in range(m):
        # Column k holds u_j(i - k).
        windows = np.lib.stride_tricks.sliding_window_view(padded[:, j], taps)[:, ::-1]
        columns.append(windows)
    return np.hstack(columns)


def fit_percent(y, yhat, detrend):
    if detrend:
        y = y - y.mean()
        yhat = yhat - yhat.mean()
    spread = np.linalg.norm(y - y.mean())
    return float(100.0 * (1.0 - np.linalg.norm(y - yhat) / spread)) if spread > 0 else float("nan")


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, not the usage block
        fail(f"{message} (see --help)")


def main():
    for stream in (sys.stdout, sys.stderr):  # names read from a file or the command line print as they are
        stream.reconfigure(errors="backslashreplace")
    parser = Parser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--inputs", required=True, help="input columns, comma-separated")
    parser.add_argument("--outputs", required=True, help="output columns, comma-separated")
    parser.add_argument("--estimation", required=True, help="FILE[:FIRST[:LAST]]")
    parser.add_argument("--validation", action="append", default=[], help="FILE[:FIRST[:LAST]] (repeatable)")
    parser.add_argument("--taps", type=int, default=300)
    parser.add_argument("--detrend", action="store_true", help="remove each scored set's mean before the fit %%")
    parser.add_argument("--json", help="also write the table as JSON to this file")
    args = parser.parse_args()
    try:
        run(args)
    except BadInput as e:
        fail(str(e))
    except MemoryError:
        fail(f"--taps {args.taps}: not enough memory for the fit (fewer taps, or shorter sets)")


def run(args):
    inputs = [c for c in args.inputs.split(",") if c]
    outputs = [c for c in args.outputs.split(",") if c]
    if not inputs or not outputs:
        raise BadInput("give at least one input and one output column")
    if args.taps < 1:
        raise BadInput("--taps must be at least 1")
    sets = [("estimation", args.estimation)] + [("validation", v) for v in args.validation]
    parsed = {spec: parse_set(spec) for _, spec in sets}  # every FILE:FIRST:LAST checked before any file is read
    if args.json:
        check_json_target(args.json, [path for path, _, _ in parsed.values()])
    coefficients = 1 + args.taps * len(inputs)
    recordings = {}

    def load(spec):
        """(regressors, outputs, scored samples) of a set; the scored samples are those whose
        lags are all measured samples of the file."""
        path, first, last = parsed[spec]
        if path not in recordings:
            recordings[path] = read_columns(path, inputs + outputs)
        data = recordings[path]
        last = len(data) if last is None else min(last, len(data))
        if not first < last:
            raise BadInput(f"{spec}: no samples in rows [{first}, {last}) ({path} holds {len(data)} data rows)")
        skipped = max(0, args.taps - 1 - first)
        if skipped >= last - first:
            raise BadInput(f"{spec}: --taps {args.taps} reaches past the set: its {last - first} samples from row "
                           f"{first} hold none whose {args.taps} lags are all measured (fewer taps, or a longer set)")
        # Only the rows the set needs: its own and the taps - 1 before it.
        lead = min(first, args.taps - 1)
        size = (last - first + lead) * coefficients * 8
        if size > MAX_REGRESSOR_BYTES:
            raise BadInput(f"{spec}: --taps {args.taps}: the lagged inputs of its {last - first} samples take "
                           f"{size / 1e9:.3g} GB, more than the {MAX_REGRESSOR_BYTES / 1e9:.3g} GB allowed (fewer taps, "
                           "or a shorter set)")
        phi = lagged(data[first - lead:last, : len(inputs)], args.taps)[lead:]
        return phi, data[first:last, len(inputs):], slice(skipped, None)

    phi, y, usable = load(args.estimation)
    if len(y[usable]) <= coefficients:
        raise BadInput(f"{args.estimation}: {len(y[usable])} samples with every lag measured for a FIR of "
                       f"{coefficients} coefficients (1 + {args.taps} taps × {len(inputs)} inputs): the fit needs "
                       "more samples than coefficients (lower --taps, or a longer estimation set)")
    fitted, *_ = np.linalg.lstsq(phi[usable], y[usable], rcond=None)

    table = []
    for name, spec in sets:
        phi_s, y_s, scored = load(spec)
        yhat = phi_s @ fitted
        row = {"set": name, "data": spec}
        for k, out in enumerate(outputs):
            value = fit_percent(y_s[scored, k], yhat[scored, k], args.detrend)
            row[out] = value if math.isfinite(value) else None  # a constant output has no fit %
        table.append(row)

    print(f"causal FIR, {args.taps} taps per input, inputs {', '.join(inputs)}"
          + (" (fit % after mean removal)" if args.detrend else ""))
    print(f"{'set':<11} {'data':<40} " + " ".join(f"{o:>14}" for o in outputs))
    for row in table:
        print(f"{row['set']:<11} {row['data']:<40} "
              + " ".join(f"{row[o]:>14.1f}" if row[o] is not None else f"{'-':>14}" for o in outputs))
    if args.json:
        write_json(args.json, {"taps": args.taps, "inputs": inputs, "outputs": outputs, "detrend": args.detrend,
                               "fit_percent": table})


if __name__ == "__main__":
    main()
