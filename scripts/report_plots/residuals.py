"""residual.png: the residual y − y* (measured − simulated) in the output's unit, one panel
per window and output, with its RMSE and the noise level the verdict estimated.

residual_ratio.png: the residual ratio (y − y*)/y in percent (the methodology paper Figs.
2b/3b). It is meant for a signal that stays away from zero, as the engine speed does; where
a signal crosses zero (a torque) the ratio has a pole, so tvid leaves out the samples with
|y| below 10 % of the window's largest |y| (their cells in estimation.csv are empty; docs/
report-format.md, fit metrics). The figure draws the cells as tvid wrote them and takes
max |r| from summary.json, the figure the terminal and `tvid check` read; the title says
how many samples were left out."""

import math

from . import common

def noise_rms(summary, split, out):
    return summary.obj("residuals").obj(split).obj(out, nullable=True).num("noise_rms")


def peak(values):
    finite = [abs(v) for v in values if math.isfinite(v)]
    return max(finite) if finite else None


def draw_residual(summary, panels, outputs, out_dir, dpi):
    fig, axes, rows, by_angle, cycle = common.figure_rows(panels, outputs, 1.9)
    for r, (split, windows) in enumerate(rows):
        for c, out in enumerate(outputs):
            ax = axes[r][c]
            unit = common.output_unit(summary, out)
            samples = sum(len(table["t"]) for _, table in windows)
            for label, table in windows:
                ax.plot(common.x_axis(table, by_angle)[0], table[f"{out}_residual"], color="tab:blue",
                        lw=0.8 if samples < 3000 else 0.4, zorder=2)
            ax.axhline(0.0, color="0.3", lw=0.7, zorder=1)
            limits = ax.get_ylim()
            sigma = noise_rms(summary, split, out)
            if sigma is not None and sigma > 0:  # the unpredictable part of the split's residual
                ax.axhspan(-sigma, sigma, color="tab:green", alpha=0.15, lw=0, zorder=0)
                for level in (-sigma, sigma):  # on top, where a dense residual hides the band
                    ax.axhline(level, color="darkgreen", ls="--", lw=1.3, zorder=4,
                               label=f"± σ_n = {sigma:.3g} {unit}: the {split} residual's noise".rstrip()
                               if level > 0 else None)
                ax.legend(loc="lower right", fontsize=7, framealpha=0.9)
                ax.set_ylim(limits)  # the residual sets the scale, not the band

            def rmse_text(label, short=False):
                rmse = common.window_metric(summary, split, label, out, "rmse")
                return "" if rmse is None else (f"RMSE {rmse:.3g}" if short else f"RMSE = {rmse:.3g} {unit}".rstrip())

            largest = peak([v for _, table in windows for v in table[f"{out}_residual"]])
            text = rmse_text(windows[0][0]) if len(windows) == 1 else ""
            if largest is not None:
                text += f"   max |y − y*| = {largest:.3g} {unit}".rstrip()
            common.decorate_row(ax, split, windows, by_angle, cycle, text.strip(), lambda label: rmse_text(label, True))
            ax.set_ylabel(common.labelled(f"{out} − {out}*", unit), fontsize=9)
    fig.suptitle(f"{common.title_of(summary)}: residual y − y* (measured − simulated)", fontsize=11)
    return common.save(fig, out_dir, "residual.png", dpi)


def ratio_shown(table, out):
    """(the ratio [%] as estimation.csv holds it, NaN where tvid left the sample out, count left out)."""
    shown = [r if math.isfinite(r) else math.nan for r in table[f"{out}_residual_ratio"]]
    return shown, sum(1 for r in shown if not math.isfinite(r))


def _ratio_text(metrics):
    """"max |r| = 16 %" from a summary.json metrics object (None: not reported)."""
    if metrics is None:
        return None
    value = metrics.num("max_abs_residual_ratio_percent")
    if value is None:
        fraction = metrics.num("max_abs_residual_ratio")  # a report from before the ratio was in percent
        value = None if fraction is None else 100.0 * fraction
    return value


def draw_ratio(summary, panels, outputs, out_dir, dpi):
    fig, axes, rows, by_angle, cycle = common.figure_rows(panels, outputs, 1.8)
    for r, (split, windows) in enumerate(rows):
        for c, out in enumerate(outputs):
            ax = axes[r][c]
            left_out = 0
            samples = sum(len(table["t"]) for _, table in windows)
            for label, table in windows:
                shown, n = ratio_shown(table, out)
                left_out += n
                ax.plot(common.x_axis(table, by_angle)[0], shown, color="tab:blue", lw=0.8 if samples < 3000 else 0.4)
            ax.axhline(0.0, color="0.3", lw=0.7, zorder=1)
            if len(windows) == 1:
                largest = _ratio_text(common.window_metrics(summary, split, windows[0][0], out))
            else:  # the row's windows: the largest of theirs, as the pooled figure is
                values = [_ratio_text(common.window_metrics(summary, split, label, out)) for label, _ in windows]
                values = [v for v in values if v is not None]
                largest = max(values) if values else None
            text = f"max |r| = {largest:.3g} %" if largest is not None else "no sample away from zero"
            if left_out:
                text += f"   ({left_out} samples with |y| < 10 % of the window's max |y| left out)"

            def window_peak(label):
                value = _ratio_text(common.window_metrics(summary, split, label, out))
                return f"max |r| {value:.2g} %" if value is not None else ""

            common.decorate_row(ax, split, windows, by_angle, cycle, text, window_peak)
            ax.set_ylabel(f"(y − y*)/y of {out} [%]", fontsize=8)
    fig.suptitle(f"{common.title_of(summary)}: residual ratio r = (y − y*)/y", fontsize=11)
    return common.save(fig, out_dir, "residual_ratio.png", dpi)


def draw(directory, out_dir, dpi):
    report = common.fit_traces(directory)
    if not report:
        return []
    summary, panels, outputs = report
    return [draw_residual(summary, panels, outputs, out_dir, dpi), draw_ratio(summary, panels, outputs, out_dir, dpi)]
