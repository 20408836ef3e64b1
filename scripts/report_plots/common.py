"""What every figure module shares: reading a report's CSV and JSON files, units, the
windows of a trace, the crank-angle axis of an engine report, and saving a PNG.

Bad input (a malformed file) raises ReportError with one line naming the file; the
dispatcher (plot_report.py) prints it and exits with status 2.
"""

import csv
import json
import math
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402


class ReportError(Exception):
    """A report file that is missing where it is required, or malformed."""


def fail(message):
    raise ReportError(message)


def exists(directory, name):
    return os.path.isfile(os.path.join(directory, name))


def number(cell):
    """A CSV cell as a float: empty is NaN, 'inf'/'-inf' as written."""
    return float(cell) if cell != "" else math.nan


def split_heading(heading):
    """(name, unit) of a column heading: tvid writes 'Tds_measured [N m]'; a heading
    without brackets has the unit ''."""
    name, bracket, rest = heading.partition(" [")
    return name, (rest[:-1] if bracket and rest.endswith("]") else "")


def read_csv_with_units(path):
    """(column names, their units, rows) of a CSV file."""
    if not os.path.isfile(path):
        fail(f"{path}: not found (is this a tvid report directory?)")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        fail(f"{path}: empty file, expected a header line")
    names, units = zip(*(split_heading(h) for h in rows[0])) if rows[0] else ((), ())
    return list(names), list(units), rows[1:]


def read_csv(path):
    """(column names without their units, rows) of a CSV file."""
    names, _, rows = read_csv_with_units(path)
    return names, rows


def read_json(path):
    if not os.path.isfile(path):
        fail(f"{path}: not found (is this a tvid report directory?)")
    try:
        with open(path) as f:
            return json.load(f)
    except json.JSONDecodeError as e:
        fail(f"{path}:{e.lineno}: not valid JSON: {e.msg}")


def column(header, name, path):
    if name not in header:
        fail(f"{path}: no column {name}")
    return header.index(name)


def table_by(header, rows, path, key, text_columns=()):
    """{value of column `key`: {column: [values]}} in order of appearance; every column but
    `key` and `text_columns` is read as numbers."""
    k_col = column(header, key, path)
    text = {k_col} | {header.index(c) for c in text_columns if c in header}
    out = {}
    for line, row in enumerate(rows, start=2):
        if len(row) != len(header):
            fail(f"{path}:{line}: {len(row)} cells, the header has {len(header)}")
        try:
            values = [c if i in text else number(c) for i, c in enumerate(row)]
        except ValueError:
            fail(f"{path}:{line}: a cell is not a number")
        table = out.setdefault(row[k_col], {h: [] for h in header})
        for h, v in zip(header, values):
            table[h].append(v)
    return out


# ---- units ---------------------------------------------------------------------------

def output_unit(summary, output):
    """The output's unit as summary.json's cost.outputs names it ('' when not given)."""
    for o in (summary or {}).get("cost", {}).get("outputs", []):
        if o.get("name") == output:
            return pretty_unit(o.get("unit", ""))
    return ""


def parameter_units(params):
    """{parameter: unit} from a params.json document ('' when not given)."""
    return {p.get("name"): pretty_unit(p.get("unit", "")) for p in (params or {}).get("parameters", [])}


_POWERS = {"^-1": "⁻¹", "^-2": "⁻²", "^2": "²", "^3": "³", "^4": "⁴"}


def pretty_unit(unit):
    """'kg m^2' as 'kg m²'."""
    for plain, superscript in _POWERS.items():
        unit = unit.replace(plain, superscript)
    return unit


def labelled(name, unit):
    """'name [unit]'; '[1]' for a dimensionless quantity, none when the unit is unknown."""
    return f"{name} [{pretty_unit(unit)}]" if unit else name


def product_unit(a, b):
    """The unit of a product of quantities in units a and b."""
    if a in ("", "1"):
        return b
    if b in ("", "1"):
        return a
    return f"{a}·{b}" if " " not in b and " " not in a else f"({a})·({b})"


def quotient_unit(a, b):
    """The unit of a quantity in a divided by one in b."""
    if b in ("", "1"):
        return a
    return f"{a or '1'}/({b})" if " " in b or "/" in b else f"{a or '1'}/{b}"


def squared_unit(u):
    if u in ("", "1"):
        return u
    return f"({u})²" if " " in u or "/" in u else f"{u}²"


# ---- a fit report's traces -------------------------------------------------------------

def outputs_of(header):
    return [h[: -len("_measured")] for h in header if h.endswith("_measured")]


def traces(directory):
    """([(split, label, {column: values})] for estimation then validation, outputs), or
    ([], []) when the directory holds no fit report's traces. The residual ratio is in %."""
    panels, outputs = [], []
    for split in ("estimation", "validation"):
        path = os.path.join(directory, f"{split}.csv")
        if not os.path.isfile(path):
            continue
        header, units, rows = read_csv_with_units(path)
        column(header, "t", path)
        outputs = outputs_of(header) or outputs
        for out in outputs:
            for suffix in ("_measured", "_simulated", "_residual", "_residual_ratio"):
                column(header, out + suffix, path)
        for label, table in table_by(header, rows, path, "window").items():
            for out in outputs:  # the ratio in percent; a report written before it was a fraction
                name = out + "_residual_ratio"
                if units[header.index(name)] != "%":
                    table[name] = [100.0 * v for v in table[name]]
            panels.append((split, label, table))
    return panels, outputs


def window_metric(summary, split, label, output, key):
    for w in (summary or {}).get(split, {}).get("windows", []):
        if w.get("window") == label:
            return (w.get("outputs", {}).get(output) or {}).get(key)
    return None


def title_of(summary):
    name = summary.get("experiment", "?")
    optimizer = summary.get("optimizer", {}).get("name", "?")
    note = ", interrupted" if summary.get("interrupted") else ""
    return f"{name} ({optimizer}{note})"


# ---- the crank-angle axis of an engine report --------------------------------------------

_CYCLES = re.compile(r"^cycles? (\d+)(?: to (\d+))?$")


def cycle_length_deg(panels):
    """The engine cycle [deg] (720 four-stroke, 360 two-stroke), read off the cycle windows'
    spans; 720 when no window is given in cycles."""
    for _, label, table in panels:
        m = _CYCLES.match(label)
        angles = [a for a in table.get("crank_deg", []) if math.isfinite(a)]
        if m and len(angles) > 1:
            cycles = int(m.group(2) or m.group(1)) - int(m.group(1)) + 1
            span = (angles[-1] - angles[0]) / cycles
            return 360.0 if abs(span - 360.0) < abs(span - 720.0) else 720.0
    return 720.0


def has_crank_angle(panels):
    return bool(panels) and all("crank_deg" in table for _, _, table in panels)


def rows_of(panels, by_angle):
    """The panels grouped into figure rows: [(split, [(label, table), ...])]. An engine
    report's windows of one split that follow each other on the crank angle (the validation
    cycles 3, 4, 5, ...) share a row, so the cycle boundaries show between them; otherwise
    each window has its own row."""
    rows = []
    for split, label, table in panels:
        if by_angle and rows and rows[-1][0] == split:
            previous = rows[-1][1][-1][1]["crank_deg"]
            here = table["crank_deg"]
            if previous and here and 0 <= here[0] - previous[-1] <= 1.0:  # at most a sample step apart
                rows[-1][1].append((label, table))
                continue
        rows.append((split, [(label, table)]))
    return rows


def row_label(windows):
    """'cycle 3' for one window; 'cycles 3 to 8' for consecutive cycle windows; else the labels."""
    if len(windows) == 1:
        return windows[0][0]
    first, last = _CYCLES.match(windows[0][0]), _CYCLES.match(windows[-1][0])
    if first and last:
        return f"cycles {first.group(1)} to {last.group(2) or last.group(1)}"
    return ", ".join(label for label, _ in windows)


def x_axis(table, use_angle):
    """(x values, axis label) of a window: the crank angle for an engine report, else time."""
    if use_angle:
        return table["crank_deg"], "crank angle [deg]"
    return table["t"], "t [s]"


def mark_cycles(ax, angles, cycle_deg, label=None):
    """Dashed lines at the cycle boundaries inside [min, max] of `angles` (the multiples of
    the cycle of the cumulative crank angle) and each cycle's number at its start; ticks
    every quarter cycle (the firing TDCs of a four-cylinder four-stroke), labelled every
    quarter, half or whole cycle as the window's length allows."""
    finite = [a for a in angles if math.isfinite(a)]
    if not finite:
        return
    lo, hi = min(finite), max(finite)
    first = None
    m = _CYCLES.match(label or "")
    if m:
        first = int(m.group(1))
    k0 = math.floor((lo + 1.0) / cycle_deg)  # the cycle that holds the first sample (1 deg of rounding)
    base = k0 * cycle_deg
    k = k0
    while base <= hi + 1e-6:
        if base >= lo - 0.51:  # a boundary inside the window (or at its first sample)
            ax.axvline(base, color="0.25", ls=(0, (4, 3)), lw=0.9, zorder=0)
        start = max(base, lo)
        if base + cycle_deg > lo + 1.0 and start < hi - 0.05 * cycle_deg:
            number = first + (k - k0) if first is not None else None
            text = f"cycle {number}" if number is not None else f"{base:.0f}°"
            ax.text(start, 1.0, " " + text, transform=ax.get_xaxis_transform(), va="top", ha="left",
                    fontsize=7, color="0.25")
        base += cycle_deg
        k += 1
    cycles = (hi - lo) / cycle_deg
    step = cycle_deg / 4 if cycles <= 2.05 else cycle_deg / 2 if cycles <= 4.05 else cycle_deg
    ax.xaxis.set_major_locator(ticker.MultipleLocator(step))
    ax.xaxis.set_minor_locator(ticker.MultipleLocator(cycle_deg / 4))
    ax.set_xlim(lo, hi)


def figure_rows(panels, outputs, row_height):
    """(fig, axes, rows, by_angle, cycle): one row of axes per figure row (rows_of), one
    column per output; wider when a row holds several cycles."""
    by_angle = has_crank_angle(panels)
    cycle = cycle_length_deg(panels) if by_angle else None
    rows = rows_of(panels, by_angle)
    widest = max(len(windows) for _, windows in rows)
    width = min(8.0 + 1.6 * (widest - 1), 16.0)
    fig, axes = plt.subplots(len(rows), len(outputs), figsize=(width * len(outputs), row_height * len(rows) + 0.9),
                             squeeze=False, layout="constrained")
    return fig, axes, rows, by_angle, cycle


def decorate_row(ax, split, windows, by_angle, cycle, title_text, window_text):
    """The row's title (`title_text`: the metrics of its one window, or pooled), its x axis,
    and for an engine row the cycle boundaries, with `window_text(label)` at the start of
    each window when the row holds several."""
    xs = [x for _, table in windows for x in x_axis(table, by_angle)[0]]
    if by_angle:
        mark_cycles(ax, xs, cycle, windows[0][0])
        if len(windows) > 1:
            for label, table in windows:
                ax.text(table["crank_deg"][0], 0.9, " " + window_text(label), transform=ax.get_xaxis_transform(),
                        va="top", ha="left", fontsize=7, color="0.15")
            low, high = ax.get_ylim()
            ax.set_ylim(low, high + 0.3 * (high - low))  # headroom for the cycles' labels
    ax.set_title(f"{split}: {row_label(windows)}    {title_text}".rstrip(), fontsize=9, loc="left")
    ax.set_xlabel(x_axis(windows[0][1], by_angle)[1], fontsize=8)
    ax.tick_params(labelsize=8)
    ax.grid(alpha=0.3)


def split_has_windows(summary, split, count):
    return len((summary or {}).get(split, {}).get("windows", [])) == count


# ---- saving ----------------------------------------------------------------------------

def fit_traces(directory):
    """(summary.json, the trace panels, the outputs) of a fit report, or None when the
    directory is not one or holds no traces."""
    if not exists(directory, "summary.json"):
        return None
    summary = read_json(os.path.join(directory, "summary.json"))
    panels, outputs = traces(directory)
    return (summary, panels, outputs) if panels and outputs else None


def save(fig, out_dir, name, dpi):
    """Write the figure as out_dir/name and return name."""
    os.makedirs(out_dir, exist_ok=True)
    fig.savefig(os.path.join(out_dir, name), dpi=dpi)
    plt.close(fig)
    return name
