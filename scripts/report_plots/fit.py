"""fit.png: measured and simulated output, one panel per window and output (estimation
windows, then validation windows), in the output's unit, against time, or for an engine
report against the crank angle with the cycle boundaries marked (the methodology paper
Figs. 2a/3a, Yoshida & Takamatsu Fig. 7). Each panel's title gives the window's Q-index,
fit % and RMSE; the figure's title gives the verdict."""

import os

from . import common
from .common import plt


def metrics_text(summary, split, label, out):
    q = common.window_metric(summary, split, label, out, "q_index_percent")
    fit = common.window_metric(summary, split, label, out, "fit_percent")
    rmse = common.window_metric(summary, split, label, out, "rmse")
    unit = common.output_unit(summary, out)
    parts = []
    if q is not None:
        parts.append(f"Q = {q:.2f} %")
    if fit is not None:
        parts.append(f"fit = {fit:.1f} %")
    if rmse is not None:
        parts.append(f"RMSE = {rmse:.3g} {unit}".rstrip())
    return "   ".join(parts)


def draw(directory, out_dir, dpi):
    if not common.exists(directory, "summary.json"):
        return []
    summary = common.read_json(os.path.join(directory, "summary.json"))
    panels, outputs = common.traces(directory)
    if not panels or not outputs:
        return []
    by_angle = common.has_crank_angle(panels)
    cycle = common.cycle_length_deg(panels) if by_angle else None
    rows, cols = len(panels), len(outputs)
    fig, axes = plt.subplots(rows, cols, figsize=(8 * cols, 2.3 * rows + 0.9), squeeze=False, layout="constrained")
    for r, (split, label, table) in enumerate(panels):
        x, xlabel = common.x_axis(table, by_angle)
        for c, out in enumerate(outputs):
            ax = axes[r][c]
            # The simulation drawn over the measurement: a thin red line on a broad grey one, so
            # both show where they coincide and the measurement's noise does not hide the model.
            ax.plot(x, table[f"{out}_measured"], color="0.62", lw=2.0, label="measured", zorder=2)
            ax.plot(x, table[f"{out}_simulated"], color="tab:red", lw=0.9, label="simulated", zorder=3)
            if by_angle:
                common.mark_cycles(ax, x, cycle, label)
            ax.set_title(f"{split}: {label}    {metrics_text(summary, split, label, out)}", fontsize=9, loc="left")
            ax.set_ylabel(common.labelled(out, common.output_unit(summary, out)), fontsize=9)
            ax.set_xlabel(xlabel, fontsize=8)
            ax.tick_params(labelsize=8)
            ax.grid(alpha=0.3)
            if r == 0:
                ax.legend(loc="lower right", fontsize=8, framealpha=0.9)
    verdict = summary.get("verdict", {}).get("summary")
    fig.suptitle(f"{common.title_of(summary)}: measured vs simulated" + (f"   (verdict: {verdict})" if verdict else ""),
                 fontsize=11)
    return [common.save(fig, out_dir, "fit.png", dpi)]
