"""What every figure module shares: reading a report's CSV and JSON files, units, the
windows of a trace, the crank-angle axis of an engine report, and saving a PNG.

Every value a figure takes from a report file is read here, through checked accessors:
read_json gives a Json (an object, with the file and the key path it was found at) whose
num, text, flag, obj, objects, nums and texts check the type of what they read;
read_table gives a Table whose number/numbers/texts name the file, line and column of a
bad cell, and whose index names a missing column. Bad input (a missing, damaged, non-UTF-8
or deeply nested file, a value of the wrong type, a missing column or key) raises
ReportError with one line naming the file and the key or column; the dispatcher
(plot_report.py) prints it and exits with status 2. A figure module never indexes a
report's data directly.
"""

import csv
import io
import json
import math
import os
import re
import stat

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402


MAX_FILE_BYTES = 1 << 30  # a report file larger than this is not one tvid wrote
csv.field_size_limit(MAX_FILE_BYTES)


class ReportError(Exception):
    """A report file that is missing where it is required, or malformed."""


def fail(message):
    """Raise ReportError: one line (control characters in names from the files escaped)."""
    raise ReportError(_escaped(message))


def exists(directory, name):
    return os.path.isfile(os.path.join(directory, name))


def _escaped(text):
    """Control characters (a line break in a name) as \\xNN."""
    return re.sub(r"[\x00-\x1f\x7f]", lambda m: f"\\x{ord(m.group()):02x}", str(text))


def _shown(text, limit=40):
    """Text for a message: control characters escaped, cut after `limit` characters."""
    text = _escaped(text)
    return text if len(text) <= limit else text[:limit] + "..."


def read_text(path):
    """The text of a report file (UTF-8; a byte-order mark is dropped), or ReportError:
    missing, not a regular file, too large, unreadable or not UTF-8."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        fail(f"{path}: not found (is this a tvid report directory?)")
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")
    if not stat.S_ISREG(st.st_mode):
        fail(f"{path}: not a regular file")
    if st.st_size > MAX_FILE_BYTES:
        fail(f"{path}: larger than 1 GiB: not a file tvid wrote")
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_FILE_BYTES + 1)
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        fail(f"{path}:{line}: not UTF-8 text (byte 0x{data[e.start]:02x}): not a file tvid wrote")
    return text[1:] if text.startswith("\ufeff") else text


# ---- JSON: every value read through a checked accessor ------------------------------------

def _kind(value):
    """What a JSON value is, for a message."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return f"the number {_shown(repr(value))}"
    if isinstance(value, str):
        return f"the text '{_shown(value)}'"
    if isinstance(value, list):
        return f"a list of {len(value)}"
    return "an object"


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _as_float(value):
    try:
        return float(value)
    except OverflowError:  # an integer beyond a double
        return math.inf if value > 0 else -math.inf


class Json:
    """A JSON object of a report file, with the file and the key path it was found at.

    A key that is absent gives the default; JSON null gives the default for a number or a
    text (tvid writes NaN and infinity as null) and, for an object or a list, only where the
    caller says the format allows it (nullable=True); anything of another type raises
    ReportError naming the file and the key path (e.g. `modes[0].shape`)."""

    __slots__ = ("value", "path", "key")

    def __init__(self, value, path, key=""):
        self.value, self.path, self.key = value, path, key

    def where(self, key):
        if isinstance(key, int):
            return f"{self.key}[{key}]"
        return f"{self.key}.{key}" if self.key else str(key)

    def wrong(self, key, expected, value):
        fail(f"{self.path}: {self.where(key)}: expected {expected}, found {_kind(value)}")

    def _get(self, key, required):
        if key not in self.value:
            if required:
                fail(f"{self.path}: {self.where(key)}: missing")
            return None, False
        return self.value[key], True

    def has(self, key):
        return key in self.value

    def keys(self):
        return list(self.value)

    def num(self, key, default=None, required=False):
        """A number (float); null or absent: the default, or ReportError when required."""
        value, _ = self._get(key, required)
        if value is None:
            if required:
                self.wrong(key, "a number", value)
            return default
        if not _is_number(value):
            self.wrong(key, "a number", value)
        return _as_float(value)

    def text(self, key, default=None, required=False):
        value, _ = self._get(key, required)
        if value is None:
            if required:
                self.wrong(key, "a text", value)
            return default
        if not isinstance(value, str):
            self.wrong(key, "a text", value)
        return value

    def label(self, key, default="?"):
        """A text or a number, as text (a window's label, a mode's number)."""
        value, _ = self._get(key, False)
        if value is None:
            return default
        if isinstance(value, str):
            return value
        if _is_number(value):
            return f"{value:g}" if isinstance(value, float) else str(value)
        self.wrong(key, "a text or a number", value)

    def flag(self, key, default=False):
        value, _ = self._get(key, False)
        if value is None:
            return default
        if not isinstance(value, bool):
            self.wrong(key, "true or false", value)
        return value

    def obj(self, key, required=False, nullable=False):
        """The object at key; absent (or null where nullable): an empty one."""
        value, present = self._get(key, required)
        if value is None and (not present or nullable):
            return Json({}, self.path, self.where(key))
        if not isinstance(value, dict):
            self.wrong(key, "an object", value)
        return Json(value, self.path, self.where(key))

    def _list(self, key, required, nullable):
        value, present = self._get(key, required)
        if value is None and (not present or nullable):
            return []
        if not isinstance(value, list):
            self.wrong(key, "a list", value)
        return value

    def objects(self, key, required=False, nullable=False):
        """The list of objects at key; absent (or null where nullable): []."""
        out = []
        for i, item in enumerate(self._list(key, required, nullable)):
            where = f"{self.where(key)}[{i}]"
            if not isinstance(item, dict):
                fail(f"{self.path}: {where}: expected an object, found {_kind(item)}")
            out.append(Json(item, self.path, where))
        return out

    def nums(self, key, required=False, nullable=False, length=None):
        """The list of numbers at key (null: NaN); absent (or null where nullable): []."""
        values = self._list(key, required, nullable)
        if length is not None and values and len(values) != length:
            fail(f"{self.path}: {self.where(key)}: expected {length} numbers, found {len(values)}")
        out = []
        for i, item in enumerate(values):
            if item is not None and not _is_number(item):
                fail(f"{self.path}: {self.where(key)}[{i}]: expected a number, found {_kind(item)}")
            out.append(math.nan if item is None else _as_float(item))
        return out

    def texts(self, key, required=False, nullable=False):
        out = []
        for i, item in enumerate(self._list(key, required, nullable)):
            if not isinstance(item, str):
                fail(f"{self.path}: {self.where(key)}[{i}]: expected a text, found {_kind(item)}")
            out.append(item)
        return out

    def number_map(self, key, required=False):
        """{name: number} of the object at key (null entries: None)."""
        o = self.obj(key, required)
        return {k: o.num(k) for k in o.keys()}


def read_json(path):
    """The JSON object of a report file as a Json."""
    text = read_text(path)
    try:
        value = json.loads(text)
    except json.JSONDecodeError as e:
        fail(f"{path}:{e.lineno}: not valid JSON: {e.msg}")
    except RecursionError:
        fail(f"{path}: not a file tvid wrote: JSON nested too deeply")
    except ValueError as e:  # e.g. an integer of more digits than Python converts
        fail(f"{path}: not valid JSON: {_shown(e, 80)}")
    if not isinstance(value, dict):
        fail(f"{path}: expected a JSON object, found {_kind(value)}")
    return Json(value, path)


def read_json_if(directory, name):
    """read_json(directory/name), or an empty Json when there is no such file."""
    path = os.path.join(directory, name)
    return read_json(path) if os.path.isfile(path) else Json({}, path)


# ---- CSV: columns by name, cells through checked accessors --------------------------------

def number(cell):
    """A CSV cell as a float: empty is NaN, 'inf'/'-inf' as written."""
    return float(cell) if cell != "" else math.nan


def split_heading(heading):
    """(name, unit) of a column heading: tvid writes 'Tds_measured [N m]'; a heading
    without brackets has the unit ''."""
    name, bracket, rest = heading.partition(" [")
    return name, (rest[:-1] if bracket and rest.endswith("]") else "")


class Table:
    """A CSV file of a report: the column names (units split off), their units and headings,
    and the rows, each as long as the header. Columns are found by name (index); cells are
    read through number/numbers/text/texts, which name the file, line and column of a bad one."""

    def __init__(self, path, headings, rows, lines):
        self.path, self.headings, self.rows, self.lines = path, headings, rows, lines
        pairs = [split_heading(h) for h in headings]
        self.names = [n for n, _ in pairs]
        self.units = [u for _, u in pairs]

    def has(self, name):
        return name in self.names

    def index(self, name):
        if name not in self.names:
            fail(f"{self.path}: no column {name} (columns: {_shown(', '.join(self.headings), 200)})")
        return self.names.index(name)

    def unit(self, name):
        return self.units[self.index(name)]

    def number(self, row, name, index=None, finite=False):
        """The cell of data row `row` (from 0) in column `name` as a float (empty: NaN);
        with finite=True, an empty cell or an infinity is refused too."""
        cell = self.rows[row][self.index(name) if index is None else index]
        try:
            value = number(cell)
        except ValueError:
            fail(f"{self.path}:{self.lines[row]}: column {name}: '{_shown(cell)}' is not a number")
        if finite and not math.isfinite(value):
            fail(f"{self.path}:{self.lines[row]}: column {name}: '{_shown(cell)}' is not a finite number")
        return value

    def numbers(self, name, finite=False):
        i = self.index(name)
        return [self.number(r, name, i, finite) for r in range(len(self.rows))]

    def text(self, row, name):
        return self.rows[row][self.index(name)]

    def texts(self, name):
        i = self.index(name)
        return [row[i] for row in self.rows]


def read_table(path, required=True):
    """The Table of a CSV file; None when it does not exist and is not required."""
    if not required and not os.path.lexists(path):
        return None
    text = read_text(path)
    rows, lines = [], []
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        header = next(reader, None)
        for row in reader:
            if row:
                rows.append(row)
                lines.append(reader.line_num)
    except csv.Error as e:
        fail(f"{path}:{reader.line_num}: not a CSV file tvid wrote: {e}")
    if not header:
        fail(f"{path}: empty file, expected a header line")
    table = Table(path, header, rows, lines)
    seen = set()
    for name in table.names:
        if name in seen:
            fail(f"{path}:1: column {name} appears twice")
        seen.add(name)
    for row, line in zip(rows, lines):
        if len(row) != len(header):
            fail(f"{path}:{line}: {len(row)} cells, the header has {len(header)}")
    return table


def table_by(table, key, text_columns=()):
    """{value of column `key`: {column: [values]}} in order of appearance; every column but
    `key` and `text_columns` is read as numbers."""
    table.index(key)
    text = {key} | set(text_columns)
    columns = {name: (table.texts(name) if name in text else table.numbers(name)) for name in table.names}
    out = {}
    for r, label in enumerate(columns[key]):
        group = out.setdefault(label, {name: [] for name in table.names})
        for name in table.names:
            group[name].append(columns[name][r])
    return out


# ---- units ---------------------------------------------------------------------------

def output_unit(summary, output):
    """The output's unit as summary.json's cost.outputs names it ('' when not given)."""
    for o in summary.obj("cost").objects("outputs"):
        if o.text("name") == output:
            return pretty_unit(o.text("unit", ""))
    return ""


def parameter_units(params):
    """{parameter: unit} from a params.json document ('' when not given)."""
    return {p.text("name", required=True): pretty_unit(p.text("unit", "")) for p in params.objects("parameters")}


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
        csv_table = read_table(path)
        csv_table.index("t")
        outputs = outputs_of(csv_table.names) or outputs
        for out in outputs:
            for suffix in ("_measured", "_simulated", "_residual", "_residual_ratio"):
                csv_table.index(out + suffix)
        for label, table in table_by(csv_table, "window").items():
            for out in outputs:  # the ratio in percent; a report written before it was a fraction
                name = out + "_residual_ratio"
                if csv_table.unit(name) != "%":
                    table[name] = [100.0 * v for v in table[name]]
            panels.append((split, label, table))
    return panels, outputs


def window_metric(summary, split, label, output, key):
    metrics = window_metrics(summary, split, label, output)
    return metrics.num(key) if metrics is not None else None


def window_metrics(summary, split, label, output):
    """The metrics object of an output in a window of a split (summary.json), or None."""
    for w in summary.obj(split).objects("windows"):
        if w.label("window", None) == label:
            metrics = w.obj("outputs").obj(output, nullable=True)
            return metrics if metrics.keys() else None
    return None


def title_of(summary):
    name = summary.text("experiment", "?")
    optimizer = summary.obj("optimizer").text("name", "?")
    note = ", interrupted" if summary.flag("interrupted") else ""
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
    return len(summary.obj(split).objects("windows")) == count


# ---- saving ----------------------------------------------------------------------------

def fit_traces(directory):
    """(summary.json, the trace panels, the outputs) of a fit report, or None when the
    directory is not one or holds no traces."""
    if not exists(directory, "summary.json"):
        return None
    summary = read_json(os.path.join(directory, "summary.json"))
    panels, outputs = traces(directory)
    return (summary, panels, outputs) if panels and outputs else None


_UNSAFE = re.compile(r'[\x00-\x1f\x7f/\\:*?"<>|]+')
_taken = {}  # {(out_dir, file name): the figure name it holds}, in this run


def file_name(name):
    """The file name of a figure whose name holds report names (an output `w/motor`): one
    path component, without a leading dot, at most 200 bytes; '/', '\\', control characters
    and the characters Windows refuses become '_'."""
    stem, ext = (name[:-4], name[-4:]) if name.endswith(".png") else (name, "")
    stem = _UNSAFE.sub("_", stem).lstrip(".- ") or "figure"
    while len(stem.encode("utf-8", "surrogateescape")) > 200:
        stem = stem[:-1]
    return stem + ext


def save(fig, out_dir, name, dpi):
    """Write the figure as out_dir/NAME and return NAME: `name` made a safe file name
    (file_name), with _2, _3, ... when two names of this run come out the same."""
    os.makedirs(out_dir, exist_ok=True)
    base = file_name(name)
    stem, ext = os.path.splitext(base)
    safe, k = base, 1
    while _taken.get((out_dir, safe), name) != name:
        k += 1
        safe = f"{stem}_{k}{ext}"
    _taken[(out_dir, safe)] = name
    for text in fig.findobj(matplotlib.text.Text):
        # A name from the report ('$' in an output's name) is drawn as written, not parsed
        # as mathtext; the tick formatters' own mathtext (log axes) is left to them.
        if "$" in text.get_text() and "\\mathdefault" not in text.get_text():
            text.set_parse_math(False)
    try:
        fig.savefig(os.path.join(out_dir, safe), dpi=dpi)
    finally:
        plt.close(fig)
    return safe


def install(staging, out_dir, names):
    """Move the figures `names` from the folder `staging` into out_dir, each renamed over
    its name there, once every target is known to be replaceable: none is a directory,
    FIFO or device (ReportError, nothing moved). Returns their paths in out_dir."""
    for name in names:
        target = os.path.join(out_dir, name)
        try:
            mode = os.lstat(target).st_mode
        except FileNotFoundError:
            continue
        if not (stat.S_ISREG(mode) or stat.S_ISLNK(mode)):
            fail(f"{target}: exists and is not a regular file: not replaced")
    paths = []
    for name in names:
        os.replace(os.path.join(staging, name), os.path.join(out_dir, name))
        paths.append(os.path.join(out_dir, name))
    return paths
