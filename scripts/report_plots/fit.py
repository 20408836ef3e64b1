"""fit.png: measured and simulated output per window and output (estimation windows, then
validation windows), in the output's unit, against time, or for an engine report against
the crank angle with the cycle boundaries marked and consecutive cycles side by side (the
methodology paper Figs. 2a/3a, Yoshida & Takamatsu Fig. 7). The titles give each window's
(or the split's pooled) Q-index, fit % and RMSE; the figure's title gives the verdict."""


from . import common


def metrics_text(metrics, unit, short=False):
    """'Q = 99.95 %   fit = 85.0 %   RMSE = 0.08 rad/s' from a metrics object (a Json, or None)."""
    if metrics is None:
        return ""
    q, fit, rmse = metrics.num("q_index_percent"), metrics.num("fit_percent"), metrics.num("rmse")
    parts = []
    if q is not None:
        parts.append(f"Q {q:.2f} %" if short else f"Q = {q:.2f} %")
    if fit is not None:
        parts.append(f"fit {fit:.1f} %" if short else f"fit = {fit:.1f} %")
    if rmse is not None and not short:
        parts.append(f"RMSE = {rmse:.3g} {unit}".rstrip())
    return ("  " if short else "   ").join(parts)


window_metrics = common.window_metrics


def row_metrics(summary, split, windows, out):
    """The window's metrics, or the split's pooled ones when the row holds the whole split."""
    if len(windows) == 1:
        return window_metrics(summary, split, windows[0][0], out), ""
    if common.split_has_windows(summary, split, len(windows)):
        pooled = summary.obj(split).obj("pooled").obj(out, nullable=True)
        return (pooled if pooled.keys() else None), "pooled: "
    return None, ""


def draw(directory, out_dir, dpi):
    report = common.fit_traces(directory)
    if not report:
        return []
    summary, panels, outputs = report
    fig, axes, rows, by_angle, cycle = common.figure_rows(panels, outputs, 2.3)
    for r, (split, windows) in enumerate(rows):
        for c, out in enumerate(outputs):
            ax = axes[r][c]
            unit = common.output_unit(summary, out)
            for i, (label, table) in enumerate(windows):
                x, _ = common.x_axis(table, by_angle)
                # The simulation drawn over the measurement: a thin red line on a broad grey one,
                # so both show where they coincide and the measurement's noise does not hide it.
                ax.plot(x, table[f"{out}_measured"], color="0.62", lw=2.0, zorder=2,
                        label="measured" if i == 0 else None)
                ax.plot(x, table[f"{out}_simulated"], color="tab:red", lw=0.9, zorder=3,
                        label="simulated" if i == 0 else None)
            metrics, prefix = row_metrics(summary, split, windows, out)
            common.decorate_row(ax, split, windows, by_angle, cycle, prefix + metrics_text(metrics, unit),
                                lambda label: metrics_text(window_metrics(summary, split, label, out), unit, True))
            ax.set_ylabel(common.labelled(out, unit), fontsize=9)
            if r == 0:
                ax.legend(loc="lower right", fontsize=8, framealpha=0.9)
    verdict = summary.obj("verdict", nullable=True).text("summary")
    fig.suptitle(f"{common.title_of(summary)}: measured vs simulated" + (f"   (verdict: {verdict})" if verdict else ""),
                 fontsize=11)
    return [common.save(fig, out_dir, "fit.png", dpi)]
