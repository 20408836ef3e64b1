"""residual.png: the residual y − y* (measured − simulated) in the output's unit, one panel
per window and output, with its RMSE and the noise level the verdict estimated.

residual_ratio.png: the residual ratio (y − y*)/y in percent (the methodology paper Figs.
2b/3b). It is meant for a signal that stays away from zero, as the engine speed does; where
a signal crosses zero (a torque) the ratio has a pole, so samples with |y| below 10 % of
the window's largest |y| are left out, and the title says how many."""

import math
import os

from . import common
from .common import plt

NEAR_ZERO = 0.10  # a sample with |y| < NEAR_ZERO · max |y| of its window has no meaningful ratio


def noise_rms(summary, split, out):
    return (summary.get("residuals", {}).get(split, {}).get(out) or {}).get("noise_rms")


def grid(panels, outputs, height):
    rows, cols = len(panels), len(outputs)
    return plt.subplots(rows, cols, figsize=(8 * cols, height * rows + 0.9), squeeze=False, layout="constrained")


def finish(fig, axes, title):
    fig.suptitle(title, fontsize=11)


def draw_residual(summary, panels, outputs, by_angle, cycle, out_dir, dpi):
    fig, axes = grid(panels, outputs, 1.9)
    for r, (split, label, table) in enumerate(panels):
        x, xlabel = common.x_axis(table, by_angle)
        for c, out in enumerate(outputs):
            ax = axes[r][c]
            unit = common.output_unit(summary, out)
            e = table[f"{out}_residual"]
            ax.plot(x, e, color="tab:blue", lw=0.8, zorder=2)
            ax.axhline(0.0, color="0.3", lw=0.7, zorder=1)
            limits = ax.get_ylim()
            sigma = noise_rms(summary, split, out)
            if sigma is not None and sigma > 0:  # the unpredictable part of the split's residual
                ax.axhspan(-sigma, sigma, color="tab:green", alpha=0.15, lw=0, zorder=0,
                           label=f"± σ_n = {sigma:.3g} {unit}: the {split} residual's noise".rstrip())
                ax.legend(loc="lower right", fontsize=7, framealpha=0.9)
                ax.set_ylim(limits)  # the residual sets the scale, not the band
            if by_angle:
                common.mark_cycles(ax, x, cycle, label)
            rmse = common.window_metric(summary, split, label, out, "rmse")
            finite = [abs(v) for v in e if math.isfinite(v)]
            text = f"RMSE = {rmse:.3g} {unit}".rstrip() if rmse is not None else ""
            if finite:
                text += f"   max |y − y*| = {max(finite):.3g} {unit}".rstrip()
            ax.set_title(f"{split}: {label}    {text}", fontsize=9, loc="left")
            ax.set_ylabel(common.labelled(f"{out} − {out}*", unit), fontsize=9)
            ax.set_xlabel(xlabel, fontsize=8)
            ax.tick_params(labelsize=8)
            ax.grid(alpha=0.3)
    finish(fig, axes, f"{common.title_of(summary)}: residual y − y* (measured − simulated)")
    return common.save(fig, out_dir, "residual.png", dpi)


def draw_ratio(summary, panels, outputs, by_angle, cycle, out_dir, dpi):
    fig, axes = grid(panels, outputs, 1.8)
    for r, (split, label, table) in enumerate(panels):
        x, xlabel = common.x_axis(table, by_angle)
        for c, out in enumerate(outputs):
            ax = axes[r][c]
            y = table[f"{out}_measured"]
            peak = max((abs(v) for v in y if math.isfinite(v)), default=0.0)
            shown, left_out = [], 0
            for v, ratio in zip(y, table[f"{out}_residual_ratio"]):
                if math.isfinite(v) and abs(v) >= NEAR_ZERO * peak and math.isfinite(ratio):
                    shown.append(100.0 * ratio)
                else:
                    shown.append(math.nan)  # a gap in the line
                    left_out += 1
            ax.plot(x, shown, color="tab:blue", lw=0.8)
            ax.axhline(0.0, color="0.3", lw=0.7, zorder=1)
            if by_angle:
                common.mark_cycles(ax, x, cycle, label)
            finite = [abs(v) for v in shown if math.isfinite(v)]
            text = f"max |r| = {max(finite):.3g} %" if finite else "no sample away from zero"
            if left_out:
                text += f"   ({left_out} samples with |y| < {NEAR_ZERO * 100:.0f} % of max |y| left out)"
            ax.set_title(f"{split}: {label}    {text}", fontsize=9, loc="left")
            ax.set_ylabel(f"(y − y*)/y of {out} [%]", fontsize=8)
            ax.set_xlabel(xlabel, fontsize=8)
            ax.tick_params(labelsize=8)
            ax.grid(alpha=0.3)
    finish(fig, axes, f"{common.title_of(summary)}: residual ratio r = (y − y*)/y")
    return common.save(fig, out_dir, "residual_ratio.png", dpi)


def draw(directory, out_dir, dpi):
    if not common.exists(directory, "summary.json"):
        return []
    summary = common.read_json(os.path.join(directory, "summary.json"))
    panels, outputs = common.traces(directory)
    if not panels or not outputs:
        return []
    by_angle = common.has_crank_angle(panels)
    cycle = common.cycle_length_deg(panels) if by_angle else None
    return [draw_residual(summary, panels, outputs, by_angle, cycle, out_dir, dpi),
            draw_ratio(summary, panels, outputs, by_angle, cycle, out_dir, dpi)]
