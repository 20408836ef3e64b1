"""Spectra of a tvid fit report: where in frequency, or in engine order, the misfit lies.

From a report directory written by `tvid fit` (docs/report-format.md):
  spectra.png  per output (rows) and split (columns): the Welch power spectral densities of
               the measured output, the simulated output and the residual in unit^2/Hz on a
               log axis (spectra.csv), the residual's dominant band shaded with its share of
               the residual variance (summary.json `residual_spectrum`) unless the residual
               passes the whiteness test (`residuals.SPLIT.OUTPUT.white`), both axes
               logarithmic, and the model's
               eigenfrequencies as vertical lines when summary.json has `modes.modes[]`
               (rigid-body modes left out)
  orders.png   experiments with a crank angle (orders.csv): per output and split, the
               amplitude of the measured output, the simulated output and the residual at
               each order, the RMS over the split's cycles, on a log axis in the output's unit

draw(directory, out_dir, dpi) writes them and returns the PNG file names written (an
empty list when the directory holds neither file). Standard library, numpy and
matplotlib (Agg backend) only.
"""

import math
import os
import re

import numpy as np

from . import common
from .common import plt

_COLUMN = re.compile(r"^(?P<output>.+)_(?P<kind>measured|simulated|residual)_psd \[(?P<unit>[^\]]*)\]$")
_STYLE = {
    "measured": dict(color="0.6", lw=2.4, alpha=0.8, label="measured"),
    "simulated": dict(color="tab:red", lw=1.1, ls="--", label="simulated"),
    "residual": dict(color="tab:blue", lw=1.3, label="residual (measured - simulated)"),
}


def _percent(share):
    """A share as the terminal writes it: "38 %", "0.39 %"."""
    return f"{100 * share:.0f} %" if share >= 0.1 else f"{100 * share:.2g} %"


def _hz(value):
    return f"{value:.0f}" if value >= 100 else f"{value:.3g}"


def _eigenfrequencies(summary):
    """(frequency_hz, kind) of the model's flexible modes, when the summary lists them."""
    out = []
    for m in summary.obj("modes", nullable=True).objects("modes", nullable=True):
        f, kind = m.num("frequency_hz"), m.text("kind", "")
        if kind == "rigid_body" or f is None or not math.isfinite(f) or not f > 0:
            continue
        out.append((f, kind))
    return out


def _spectra(path):
    """{split: {"f": array, output: {kind: array}}}, and {output: density unit}."""
    table = common.read_table(path)
    columns = []
    units = {}
    for heading, name in zip(table.headings, table.names):
        m = _COLUMN.match(heading)
        if m:
            columns.append((name, m["output"], m["kind"], table.numbers(name)))
            units[m["output"]] = m["unit"]
    for output in units:
        for kind in ("measured", "simulated", "residual"):
            table.index(f"{output}_{kind}_psd")
    splits, frequencies = table.texts("split"), table.numbers("frequency", finite=True)
    data = {}
    for r, (split_name, f) in enumerate(zip(splits, frequencies)):
        split = data.setdefault(split_name, {"f": []})
        split["f"].append(f)
        for _, output, kind, values in columns:
            split.setdefault(output, {}).setdefault(kind, []).append(values[r])
    for split in data.values():
        split["f"] = np.array(split["f"])
        for key, value in split.items():
            if key != "f":
                for kind in value:
                    value[kind] = np.array(value[kind])
    return data, units


def _residual_spectrum(summary, split, output):
    """summary.json's residual_spectrum.SPLIT.OUTPUT (empty when absent or null)."""
    return summary.obj("residual_spectrum", nullable=True).obj(split, nullable=True).obj(output, nullable=True)


def _white(summary, split, output):
    """The Ljung-Box p of a residual that passes the whiteness test (summary.json's
    residuals.SPLIT.OUTPUT.white), else None."""
    w = summary.obj("residuals", nullable=True).obj(split, nullable=True).obj(output, nullable=True)
    return w.num("ljung_box_p", 1.0) if w.flag("white") else None


def _draw_spectra(directory, out_dir, dpi, summary):
    data, units = _spectra(os.path.join(directory, "spectra.csv"))
    splits = [s for s in ("estimation", "validation") if s in data and len(data[s]["f"]) > 1]
    outputs = list(units)
    if not splits or not outputs:
        return []
    modes = _eigenfrequencies(summary)
    fig, axes = plt.subplots(len(outputs), len(splits), figsize=(7.5 * len(splits), 3.4 * len(outputs) + 0.6),
                             squeeze=False)
    for r, output in enumerate(outputs):
        for c, split in enumerate(splits):
            ax = axes[r][c]
            f = data[split]["f"]
            for kind in ("measured", "simulated", "residual"):
                d = data[split][output][kind]
                keep = (f > 0) & np.isfinite(d) & (d > 0)  # 0 Hz holds nothing: each segment's mean is removed
                ax.loglog(f[keep], d[keep], **_STYLE[kind])
            title = f"{split}: {output}"
            peak = _residual_spectrum(summary, split, output).obj("frequency", nullable=True)
            band = peak.nums("band_hz", nullable=True, length=2)
            share, peak_hz = peak.num("share"), peak.num("peak_hz")
            white = _white(summary, split, output)
            if white is not None:  # the whiteness test passes: no band stands out of the noise
                title += f"   residual white (Ljung-Box p = {white:.2g}): no peak band"
            elif band and all(math.isfinite(b) for b in band) and share is not None and peak_hz is not None:
                lo, hi = band
                ax.axvspan(max(lo, f[1]), hi, color="tab:blue", alpha=0.12, lw=0,
                           label=f"residual band: {_percent(share)} of its variance")
                title += f"   residual peak {_hz(peak_hz)} Hz ({_percent(share)} in {_hz(lo)}-{_hz(hi)} Hz)"
            for i, (fm, kind) in enumerate(modes):
                if fm <= f[-1]:
                    ax.axvline(fm, color="tab:green", lw=0.9, ls=":",
                               label="model eigenfrequency" if i == 0 else None)
            ax.set_xlim(f[1], f[-1])
            ax.set_title(title, fontsize=9)
            ax.set_ylabel(f"PSD of {output} [{units[output]}]")
            ax.grid(alpha=0.3, which="both")
            if r == 0 and c == 0:
                ax.legend(loc="lower left", fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("frequency [Hz]")
    fig.suptitle(f"{summary.text('experiment', '')}: power spectral densities (Welch, Hann segments)".strip(": "),
                 fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.35 / fig.get_figheight()))
    return [common.save(fig, out_dir, "spectra.png", dpi)]


def _draw_orders(directory, out_dir, dpi, summary):
    csv_table = common.read_table(os.path.join(directory, "orders.csv"))
    if not csv_table.rows:
        return []
    split_of, output_of, unit_of = csv_table.texts("split"), csv_table.texts("output"), csv_table.texts("unit")
    window_of, cycle_of, order_of = csv_table.texts("window"), csv_table.texts("cycle"), \
        csv_table.numbers("order", finite=True)
    amplitudes = {kind: csv_table.numbers(f"{kind}_amplitude") for kind in ("measured", "simulated", "residual")}
    # {(split, output): {order: {kind: [amplitudes over cycles]}}}
    table, units, cycles = {}, {}, {}
    for r, key in enumerate(zip(split_of, output_of)):
        units[key[1]] = unit_of[r]
        cycles.setdefault(key, set()).add((window_of[r], cycle_of[r]))
        per_order = table.setdefault(key, {}).setdefault(order_of[r], {})
        for kind in ("measured", "simulated", "residual"):
            per_order.setdefault(kind, []).append(amplitudes[kind][r])
    splits = [s for s in ("estimation", "validation") if any(k[0] == s for k in table)]
    outputs = list(units)
    fig, axes = plt.subplots(len(outputs), len(splits), figsize=(7.5 * len(splits), 3.4 * len(outputs) + 0.6),
                             squeeze=False)
    colors = {"measured": "0.6", "simulated": "tab:red", "residual": "tab:blue"}
    for r, output in enumerate(outputs):
        for c, split in enumerate(splits):
            ax = axes[r][c]
            per_order = table.get((split, output), {})
            orders = sorted(per_order)
            x = np.arange(len(orders))
            for i, kind in enumerate(("measured", "simulated", "residual")):
                rms = [math.sqrt(np.nanmean(np.square(per_order[o][kind]))) for o in orders]
                ax.bar(x + (i - 1) * 0.27, rms, width=0.27, color=colors[kind], label=kind, log=True)
            ax.set_xticks(x)
            ax.set_xticklabels([f"{o:g}" for o in orders], fontsize=7)
            n = len(cycles.get((split, output), ()))
            peak = _residual_spectrum(summary, split, output).obj("order", nullable=True)
            share, order, orders_share = peak.num("share"), peak.num("order"), peak.num("orders_share")
            title = f"{split}: {output}, RMS over {n} cycle{'s' if n != 1 else ''}"
            white = _white(summary, split, output)
            if white is not None:
                title += f"   residual white (Ljung-Box p = {white:.2g}): no order stands out"
            elif share is not None and order is not None:
                title += f"   residual: {_percent(share)} of its variance at order {order:g}"
                if orders_share is not None:
                    title += f", {_percent(orders_share)} up to order {peak.num('max_order', 0.0):g}"
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("order [per revolution of the angle channel's shaft]")
            ax.set_ylabel(f"amplitude of {output} [{units[output]}]")
            ax.grid(alpha=0.3, axis="y", which="both")
            if r == 0 and c == 0:
                ax.legend(loc="upper right", fontsize=7)
    fig.suptitle(f"{summary.text('experiment', '')}: order spectrum, cycle by cycle of the crank angle".strip(": "),
                 fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.35 / fig.get_figheight()))
    return [common.save(fig, out_dir, "orders.png", dpi)]


def draw(directory, out_dir, dpi):
    """Writes spectra.png (and orders.png for an engine) to out_dir; returns the names written."""
    summary = common.read_json_if(directory, "summary.json")
    written = []
    if os.path.isfile(os.path.join(directory, "spectra.csv")):
        written += _draw_spectra(directory, out_dir, dpi, summary)
    if os.path.isfile(os.path.join(directory, "orders.csv")):
        written += _draw_orders(directory, out_dir, dpi, summary)
    return written


if __name__ == "__main__":
    import sys

    report = sys.argv[1] if len(sys.argv) > 1 else "."
    target = sys.argv[2] if len(sys.argv) > 2 else report
    os.makedirs(target, exist_ok=True)
    for name in draw(report, target, 110):
        print(os.path.join(target, name))
