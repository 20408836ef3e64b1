"""Figures of a `tvid batch` directory (docs/report-format.md, "Batch fits").

    draw(batch_dir, out_dir, dpi) -> list of the PNG file names written

cross_matrix.png       (`--cross` only) the cross-cycle matrix: fit % of the parameters
                       fitted on one job (y) simulated on another job's estimation data (x),
                       the value in each cell; the diagonal is each job's own fit. With
                       several outputs, cross_matrix_OUTPUT.png per output.
parameter_spread.png   one panel per free parameter: its value per successful job (with
                       its standard error as an error bar when batch.csv has a
                       `std_error_NAME` column), the mean and the mean ± std band, in the
                       parameter's unit; jobs flagged as outliers (robust z) in red.

Reads batch.csv, batch_summary.json, parameter_stability.csv and matrix_long.csv; a
directory without batch.csv gives no figure. Standard library, numpy and matplotlib (Agg).
"""

import math
import os

import numpy as np
from matplotlib import ticker

from . import common
from .common import plt


def _labelled(name, unit):
    return f"{name} [{unit}]" if unit else f"{name} [unit unknown]"


def _tick_labels(ax, ids, axis="x", highlight=()):
    """Job ids as tick labels, thinned to about 30 when there are many; highlighted ids in red."""
    step = max(1, math.ceil(len(ids) / 30))
    ticks = list(range(0, len(ids), step))
    labels = [ids[k] for k in ticks]
    if axis == "x":
        ax.set_xticks(ticks)
        ax.set_xticklabels(labels, rotation=60, ha="right", fontsize=7)
        tick_texts = ax.get_xticklabels()
    else:
        ax.set_yticks(ticks)
        ax.set_yticklabels(labels, fontsize=7)
        tick_texts = ax.get_yticklabels()
    for text in tick_texts:
        if text.get_text() in highlight:
            text.set_color("tab:red")
            text.set_fontweight("bold")


def _outliers(summary):
    """{subject: set of job ids} from batch_summary.json's outliers."""
    flagged = {}
    for o in summary.objects("outliers", nullable=True):
        flagged.setdefault(o.text("subject", ""), set()).add(o.text("id", ""))
    return flagged


def _draw_cross(batch_dir, out_dir, dpi, summary):
    table = common.read_table(os.path.join(batch_dir, "matrix_long.csv"), required=False)
    if table is None or not table.rows:
        return []
    fitted, validated, output_of = table.texts("fitted"), table.texts("validated"), table.texts("output")
    fit_percent = table.numbers("fit_percent")
    jobs, outputs = [], []
    for r in range(len(table.rows)):
        for value, seen in ((fitted[r], jobs), (validated[r], jobs), (output_of[r], outputs)):
            if value not in seen:
                seen.append(value)
    index = {job: k for k, job in enumerate(jobs)}
    flagged = _outliers(summary).get("mean_cross_fit", set())
    written = []
    for output in outputs:
        fit = np.full((len(jobs), len(jobs)), np.nan)
        for r in range(len(table.rows)):
            if output_of[r] == output:
                fit[index[fitted[r]], index[validated[r]]] = fit_percent[r]
        n = len(jobs)
        size = min(14.0, 3.0 + 0.55 * n)
        fig, ax = plt.subplots(figsize=(size + 1.5, size), layout="constrained")
        finite = fit[np.isfinite(fit)]
        low = float(np.min(finite)) if finite.size else 0.0
        high = float(np.max(finite)) if finite.size else 100.0
        # One diverging cell (a fit of -2000 %) would flatten every other colour: the scale
        # ends 6 robust standard deviations (1.4826 MAD) below the median, lower cells take
        # its darkest colour (the colour bar's arrow) and keep their value as text.
        clipped = False
        if finite.size >= 3:
            middle_fit = float(np.median(finite))
            spread = 1.4826 * float(np.median(np.abs(finite - middle_fit)))
            if spread > 0 and low < middle_fit - 6.0 * spread:
                low, clipped = middle_fit - 6.0 * spread, True
        if high - low < 1e-9:
            low, high = low - 1.0, high + 1.0
        cmap = plt.get_cmap("viridis").copy()
        cmap.set_bad("lightgray")
        image = ax.imshow(np.ma.masked_invalid(fit), cmap=cmap, vmin=low, vmax=high, origin="upper",
                          aspect="equal")
        bar = fig.colorbar(image, ax=ax, shrink=0.85, extend="min" if clipped else "neither")
        bar.set_label(f"fit of {output} [%]" + (f" (below {low:.1f} %: darkest)" if clipped else ""))
        if n <= 24:
            middle = 0.5 * (low + high)
            for i in range(n):
                for j in range(n):
                    text = "failed" if not math.isfinite(fit[i, j]) else f"{fit[i, j]:.2f}"
                    ax.text(j, i, text, ha="center", va="center", fontsize=8 if n <= 10 else 6,
                            color="black" if not math.isfinite(fit[i, j]) or fit[i, j] > middle else "white",
                            fontweight="bold" if i == j else "normal")
        _tick_labels(ax, jobs, "x")
        _tick_labels(ax, jobs, "y", highlight=flagged)
        ax.set_xlabel("validated on the estimation data of job [job id]")
        ax.set_ylabel("parameters fitted on job [job id]")
        title = f"Cross-validation fit % of {output} ({n} jobs)"
        diagonal = np.diag(fit)
        off = fit[~np.eye(n, dtype=bool)]
        if np.isfinite(diagonal).any() and np.isfinite(off).any():
            title += (f"\nmedian on own data {np.nanmedian(diagonal):.2f} %, "
                      f"on the others' {np.nanmedian(off):.2f} %")
        if flagged:
            title += "\nred: outlier by mean cross-validation fit"
        ax.set_title(title, fontsize=10)
        name = "cross_matrix.png" if len(outputs) == 1 else f"cross_matrix_{output}.png"
        written.append(common.save(fig, out_dir, name, dpi))
    return written


def _draw_spread(batch_dir, out_dir, dpi, summary):
    table = common.read_table(os.path.join(batch_dir, "batch.csv"))
    if not table.rows:
        return []
    ok = [r for r, status in enumerate(table.texts("status")) if status == "ok"]
    if not ok:
        return []
    units = {}
    stability = common.read_table(os.path.join(batch_dir, "parameter_stability.csv"), required=False)
    if stability is not None:
        units = dict(zip(stability.texts("parameter"), stability.texts("unit")))
    stability_json = summary.obj("parameter_stability", nullable=True)
    for name in stability_json.keys():
        units.setdefault(name, stability_json.obj(name, nullable=True).text("unit", ""))
    # The free parameters: the columns between message and cost.
    first, last = table.index("message") + 1, table.index("cost")
    parameters = table.names[first:last]
    if not parameters:
        return []
    flagged = _outliers(summary)
    every_id = table.texts("id")
    ids = [every_id[r] for r in ok]
    x = np.arange(len(ids))
    ncols = min(4, len(parameters))
    nrows = math.ceil(len(parameters) / ncols)
    width = max(3.6, min(8.0, 1.6 + 0.22 * len(ids)))
    fig, axes = plt.subplots(nrows, ncols, figsize=(width * ncols, 2.9 * nrows + 0.8), squeeze=False,
                             layout="constrained")
    any_outlier = False
    for k, name in enumerate(parameters):
        ax = axes[k // ncols][k % ncols]
        every = table.numbers(name)
        values = np.array([every[r] for r in ok])
        errors = None
        if table.has("std_error_" + name):
            every_error = table.numbers("std_error_" + name)
            errors = np.array([every_error[r] for r in ok])
        finite = values[np.isfinite(values)]
        if finite.size:
            mean = float(np.mean(finite))
            std = float(np.std(finite, ddof=1)) if finite.size > 1 else 0.0
            ax.axhspan(mean - std, mean + std, color="tab:blue", alpha=0.12, lw=0, label="mean ± std")
            ax.axhline(mean, color="tab:blue", lw=1.0, label="mean")
        outlier = np.array([job in flagged.get(name, set()) for job in ids])
        any_outlier = any_outlier or bool(outlier.any())
        if errors is not None and np.isfinite(errors).any():
            ax.errorbar(x, values, yerr=np.where(np.isfinite(errors), errors, 0.0), fmt="none", ecolor="0.4",
                        elinewidth=0.8, capsize=2)
        ax.plot(x[~outlier], values[~outlier], "o", color="black", ms=4)
        if outlier.any():
            ax.plot(x[outlier], values[outlier], "o", color="tab:red", ms=6, label="outlier")
        cv = ""
        if finite.size > 1 and mean != 0.0:
            percent = 100.0 * std / abs(mean)
            cv = f"  (cv {percent:.0f} %)" if percent >= 10 else f"  (cv {percent:.2g} %)"
        ax.set_title(name + cv, fontsize=9)
        ax.set_ylabel(_labelled(name, units.get(name, "")), fontsize=8)
        ax.tick_params(axis="y", labelsize=7)
        # Plain numbers to six digits: no "1e-3" offset text apart from the axis label's unit.
        ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _pos: f"{v:.6g}"))
        _tick_labels(ax, ids, "x", highlight=flagged.get(name, set()))
        ax.set_xlabel("job [id]", fontsize=8)
        ax.grid(axis="y", alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7, loc="best")
    for k in range(len(parameters), nrows * ncols):
        axes[k // ncols][k % ncols].set_visible(False)
    title = f"Parameter spread over {len(ids)} jobs ({summary.text('experiment', os.path.basename(batch_dir))})"
    if any_outlier:
        title += "; red: outlier by robust z-score (|z| > 3.5)"
    fig.suptitle(title, fontsize=11)
    return [common.save(fig, out_dir, "parameter_spread.png", dpi)]


def draw(batch_dir, out_dir, dpi):
    """The batch figures for batch_dir, written to out_dir; [] when it holds no batch.csv."""
    if not os.path.isfile(os.path.join(batch_dir, "batch.csv")):
        return []
    os.makedirs(out_dir, exist_ok=True)
    summary = common.read_json_if(batch_dir, "batch_summary.json")
    return _draw_cross(batch_dir, out_dir, dpi, summary) + _draw_spread(batch_dir, out_dir, dpi, summary)
