"""From a directory written by `tvid sensitivity`:

sensitivity_OUTPUT.png   p·∂y/∂p over time, one panel per free parameter (the methodology paper
                         Figs. 4-5): the change of y, in y's unit, for a 100 % change of p;
                         ∂y/∂p for a parameter at 0.
sensitivity_ranking.png  the free parameters ranked by the RMS of p·∂y/∂p over the scored
                         samples (ranking.csv), one panel per output, log scale: a parameter
                         whose bar is decades below the first moves the output too little
                         to be identified from it.

sensitivity.json records no units; they are read from the fit report whose params.json
the run used (`--params` in its command) or from the directory above (the default
REPORT/sensitivity)."""

import bisect
import math
import os
import shlex

from . import common
from .common import plt


def report_behind(directory, info):
    """The fit report directory whose params.json the run used (or the one above the
    sensitivity directory), or None."""
    candidates = []
    try:
        words = shlex.split(info.text("command", ""))
    except ValueError:
        words = []
    for i, w in enumerate(words):
        if w == "--params" and i + 1 < len(words):
            candidates.append(words[i + 1])
        elif w.startswith("--params="):
            candidates.append(w[len("--params="):])
    candidates.append(os.path.join(os.path.dirname(os.path.abspath(directory)), "params.json"))
    for path in candidates:
        report = os.path.dirname(path)
        if os.path.isfile(path) and os.path.isfile(os.path.join(report, "summary.json")):
            return report
    return None


def report_units(report, info):
    """({output: unit}, {parameter: unit}) from the fit report, if any."""
    if report is None:
        return {}, {}
    try:
        params = common.parameter_units(common.read_json(os.path.join(report, "params.json")))
        summary = common.read_json(os.path.join(report, "summary.json"))
    except common.ReportError:
        return {}, {}  # not a report's files after all: no units from it
    return {o: common.output_unit(summary, o) for o in info.texts("outputs")}, params


def crank_angle_of(report):
    """{window: [(time, crank angle [deg])]} from the fit report's traces (an engine report's),
    and its cycle length; ({}, None) without."""
    if report is None:
        return {}, None
    try:
        panels, _ = common.traces(report)
    except common.ReportError:
        return {}, None
    if not common.has_crank_angle(panels):
        return {}, None
    angle = {label: sorted(zip(table["t"], table["crank_deg"])) for _, label, table in panels}
    return angle, common.cycle_length_deg(panels)


def angle_at(samples, t):
    """The crank angle of the trace sample at time t (the files write time to 9 and 10
    significant digits), or None."""
    i = bisect.bisect_left(samples, (t,))
    for j in (i - 1, i):
        if 0 <= j < len(samples) and abs(samples[j][0] - t) <= 1e-8 * max(1.0, abs(t)):
            return samples[j][1]
    return None


def on_crank_angle(values, angle):
    """The series with time replaced by the crank angle when every sample has one, else None."""
    out = {}
    for p, by_output in values.items():
        out[p] = {}
        for o, by_window in by_output.items():
            out[p][o] = {}
            for w, (t, s) in by_window.items():
                a = [angle_at(angle.get(w, []), x) for x in t]
                if any(v is None for v in a):
                    return None
                out[p][o][w] = (a, s)
    return out


def read_series(directory, info, free, raw):
    table = common.read_table(os.path.join(directory, "sensitivity.csv"))
    windows, times, outputs = table.texts("window"), table.numbers("time"), table.texts("output")
    values = {p: {} for p in free}
    for p in free:
        column = table.numbers(("d_" if raw[p] else "s_") + p)
        for w, t, o, v in zip(windows, times, outputs, column):
            series = values[p].setdefault(o, {}).setdefault(w, ([], []))
            series[0].append(t)
            series[1].append(v)
    return values


def parameter_values(info):
    """{parameter: value} of sensitivity.json's parameters (None where null)."""
    return {q.text("name", required=True): q.num("value") for q in info.objects("parameters")}


def draw_series(info, free, raw, values, out_units, par_units, cycle, out_dir, dpi):
    """One figure per output; against the crank angle when `cycle` is given."""
    names = []
    value_of = parameter_values(info)
    for out in info.texts("outputs"):
        unit = out_units.get(out, "")
        cols = 2 if len(free) > 3 else 1
        n_rows = math.ceil(len(free) / cols)
        fig, axes = plt.subplots(n_rows, cols, figsize=(6.5 * cols, 1.9 * n_rows + 0.9), squeeze=False, sharex=True, layout="constrained")
        for i, p in enumerate(free):
            ax = axes[i // cols][i % cols]
            series = values[p].get(out, {})
            for t, s in series.values():  # one line per window
                ax.plot(t, s, color="tab:purple", lw=0.9)
            if cycle and series:
                common.mark_cycles(ax, [a for t, _ in series.values() for a in t], cycle, next(iter(series)))
            pu = par_units.get(p, "")
            value = value_of.get(p)
            title = f"{p} = {math.nan if value is None else value:.4g} {pu}".rstrip()
            if raw[p]:  # said on the panel: its curve is of another quantity than the others'
                title += f": at 0, p·∂{out}/∂p vanishes; shown unscaled, ∂{out}/∂{p}"
            ax.set_title(title, fontsize=9, loc="left", color="tab:red" if raw[p] else "black")
            if raw[p]:
                ax.set_ylabel(common.labelled(f"∂{out}/∂{p}", common.quotient_unit(unit, pu) if unit else ""),
                              fontsize=8)
            else:
                ax.set_ylabel(common.labelled(f"{p}·∂{out}/∂{p}", unit), fontsize=8)
            ax.tick_params(labelsize=8)
            ax.grid(alpha=0.3)
        for j in range(len(free), n_rows * cols):
            axes[j // cols][j % cols].set_visible(False)
        for c in range(cols):  # the lowest panel of each column carries the time axis
            last = axes[max(i // cols for i in range(len(free)) if i % cols == c)][c]
            last.xaxis.set_tick_params(labelbottom=True)
            last.set_xlabel("crank angle [deg]" if cycle else "t [s]", fontsize=9)
        unscaled = [p for p in free if raw[p]]
        fig.suptitle(f"{info.text('experiment', '?')}: scaled sensitivities p·∂{out}/∂p "
                     f"(change of {out} for a 100 % change of p)"
                     + (f"\n{', '.join(unscaled)} at 0: unscaled ∂{out}/∂p (red titles)" if unscaled else ""),
                     fontsize=11)
        names.append(common.save(fig, out_dir, f"sensitivity_{out}.png", dpi))
    return names


def relative_errors(report):
    """{parameter: standard error / |value|} from the fit report's params.json, if any."""
    if report is None:
        return {}
    try:
        params = common.read_json(os.path.join(report, "params.json"))
    except common.ReportError:
        return {}
    out = {}
    for p in params.objects("parameters"):
        se, value = p.num("std_error"), p.num("value")
        if se is not None and value:
            out[p.text("name", required=True)] = se / abs(value)
        elif not p.flag("determined", True):
            out[p.text("name", required=True)] = math.inf  # undetermined: a null direction of the fit
    return out


def draw_ranking(info, out_units, errors, out_dir, dpi):
    ranking = info.obj("ranking", nullable=True)
    # Per output, its rows: rank, parameter, rms_scaled, relative, value, rms_raw.
    ranked = {o: [{"rank": r.num("rank", 0.0), "parameter": r.text("parameter", required=True),
                   "rms_scaled": r.num("rms_scaled"), "relative": r.num("relative"), "value": r.num("value"),
                   "rms_raw": r.num("rms_raw", 0.0)} for r in ranking.objects(o, nullable=True)]
              for o in info.texts("outputs")}
    outputs = [o for o in info.texts("outputs") if ranked[o]]
    if not outputs:
        return []
    n = max(len(ranked[o]) for o in outputs)
    fig, axes = plt.subplots(1, len(outputs), figsize=(7.5 * len(outputs), 0.32 * n + 1.8), squeeze=False, layout="constrained")
    for ax, out in zip(axes[0], outputs):
        rows = sorted(ranked[out], key=lambda r: r["rank"])
        names = [r["parameter"] for r in rows]
        rms = [r["rms_scaled"] for r in rows]
        shown = [v if v is not None and v > 0 else math.nan for v in rms]
        y = list(range(len(rows)))
        ax.barh(y, shown, color="tab:purple", alpha=0.8)
        ax.set_yticks(y)
        ax.set_yticklabels(names, fontsize=9)
        ax.invert_yaxis()  # rank 1 on top
        ax.set_xscale("log")
        positive = [v for v in shown if math.isfinite(v)]
        if positive:  # the data's decades and no more: the labels stand in a column right of the axes
            lo, hi = min(positive), max(positive)
            ax.set_xlim(10 ** math.floor(math.log10(lo) - 0.1), 10 ** math.ceil(math.log10(hi) + 0.1))
        for yi, r, v in zip(y, rows, shown):
            rel = r["relative"]
            if math.isfinite(v):
                text = f"{100 * rel:.3g} %" if rel is not None else ""
                se = errors.get(r["parameter"])
                if se is not None:
                    percent = 100 * se
                    text += "   σ/|p| undetermined" if math.isinf(se) else \
                        f"   σ/|p| {percent:.2g} %" if percent < 100 else f"   σ/|p| {percent:.0f} %"
                ax.text(1.02, yi, text, va="center", fontsize=8, transform=ax.get_yaxis_transform(), clip_on=False)
            elif r["value"] == 0:  # p·∂y/∂p vanishes at p = 0: no bar, its raw RMS instead
                ax.text(0.01, yi, f"at {r['parameter']} = 0: RMS ∂{out}/∂{r['parameter']} = {r['rms_raw']:.3g}",
                        transform=ax.get_yaxis_transform(), va="center", fontsize=8, color="0.3")
        ax.set_xlabel(common.labelled(f"RMS of p·∂{out}/∂p", out_units.get(out, "")), fontsize=9)
        ax.grid(alpha=0.3, axis="x", which="both")
        ax.set_title(f"{out}: labels give the % of the first"
                     + ("\nand σ/|p|, the fit's relative standard error (params.json)" if errors else ""),
                     fontsize=9, loc="left")
    fig.suptitle(f"{info.text('experiment', '?')}: parameters ranked by scaled sensitivity", fontsize=11)
    return [common.save(fig, out_dir, "sensitivity_ranking.png", dpi)]


def draw(directory, out_dir, dpi):
    if not common.exists(directory, "sensitivity.json"):
        return []
    info = common.read_json(os.path.join(directory, "sensitivity.json"))
    free = info.texts("free_parameters")
    if not free:
        common.fail(f"{info.path}: free_parameters: no free parameters")
    value_of = parameter_values(info)
    raw = {p: value_of.get(p) == 0 for p in free}  # p·∂y/∂p is 0 for a parameter at 0: ∂y/∂p instead
    values = read_series(directory, info, free, raw)
    report = report_behind(directory, info)
    out_units, par_units = report_units(report, info)
    angle, cycle = crank_angle_of(report)
    by_angle = on_crank_angle(values, angle) if angle else None
    if by_angle is not None:
        values = by_angle
    else:
        cycle = None
    return draw_series(info, free, raw, values, out_units, par_units, cycle, out_dir, dpi) + \
        draw_ranking(info, out_units, relative_errors(report), out_dir, dpi)
