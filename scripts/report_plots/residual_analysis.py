"""residual_analysis.png: the residual analysis of a fit as the System Identification
Toolbox's resid() shows it, from summary.json's `residual_analysis`
(docs/report-format.md). One row per split and output: the autocorrelation of the output's
residual at lags 0 … M, then the cross-correlation of each input with that residual at lags
−M … M, each with its 99 % confidence band shaded and the lags outside it in red. A
correlation at a positive lag ties the residual to earlier values of the input: a dynamic
from that input the model does not have. The verdict's findings on an input or a residual
are named in the panel's title."""

import math
import os

from . import common
from .common import plt, ticker


def _findings(summary):
    """{(code, subject)} of the verdict's findings."""
    return {(f.text("code", ""), f.text("subject", "")) for f in summary.obj("verdict").objects("findings")}


def _panel(ax, lags, values, band, title, xlabel, untested=()):
    """Stems at each lag (grey inside the band, red outside it; `untested` lags, such as an
    autocorrelation's lag 0, grey whatever their value), the band shaded."""
    ax.axhspan(-band, band, color="tab:blue", alpha=0.15, lw=0, label=f"99 % band ±{band:.3g}")
    for level in (-band, band):
        ax.axhline(level, color="tab:blue", lw=0.8, ls="--")
    ax.axhline(0.0, color="0.3", lw=0.7)
    inside = [(k, v) for k, v in zip(lags, values) if math.isfinite(v) and (abs(v) <= band or k in untested)]
    outside = [(k, v) for k, v in zip(lags, values) if math.isfinite(v) and abs(v) > band and k not in untested]
    for points, color in ((inside, "0.25"), (outside, "tab:red")):
        if points:
            ks, vs = zip(*points)
            ax.vlines(ks, 0.0, vs, color=color, lw=1.2)
            ax.plot(ks, vs, "o", color=color, ms=3.5,
                    label="outside the band" if color == "tab:red" else None)
    finite = [abs(v) for v in values if math.isfinite(v)]
    top = max([band * 1.6] + finite) * 1.1
    ax.set_ylim(-top, top)
    ax.set_xlim(min(lags) - 0.8, max(lags) + 0.8)
    ax.xaxis.set_major_locator(ticker.MaxNLocator(integer=True))
    ax.set_title(title, fontsize=9, loc="left")
    ax.set_xlabel(xlabel, fontsize=8)
    ax.tick_params(labelsize=8)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=7, framealpha=0.9)


def _outside_text(lags_outside, tested):
    return f"{len(lags_outside)} of {tested} lags outside"


def draw(directory, out_dir, dpi):
    if not common.exists(directory, "summary.json"):
        return []
    summary = common.read_json(os.path.join(directory, "summary.json"))
    analysis = summary.obj("residual_analysis", nullable=True)
    rows = []  # (split, output, acf object, [(input, ccf object)])
    for split in ("estimation", "validation"):
        block = analysis.obj(split, nullable=True)
        outputs = block.obj("outputs", nullable=True)
        inputs = block.obj("inputs", nullable=True)
        for output in outputs.keys():
            acf = outputs.obj(output, nullable=True)
            if not acf.keys():
                continue
            ccfs = [(name, inputs.obj(name).obj(output, nullable=True)) for name in inputs.keys()]
            rows.append((split, output, acf, [(n, c) for n, c in ccfs if c.keys()]))
    if not rows:
        return []
    findings = _findings(summary)
    columns = 1 + max(len(ccfs) for *_, ccfs in rows)
    fig, axes = plt.subplots(len(rows), columns, figsize=(5.2 * columns, 2.9 * len(rows) + 0.8), squeeze=False,
                             layout="constrained")
    for r, (split, output, acf, ccfs) in enumerate(rows):
        values = acf.nums("acf", required=True)
        band = acf.num("band", required=True)
        outside = acf.nums("lags_outside")
        title = f"{split}: autocorrelation of the {output} residual\n{_outside_text(outside, len(values) - 1)}"
        if split == "estimation" and (("residuals_not_white", output) in findings
                                      or ("residual_autocorrelation", output) in findings):
            title += ": not white"
        _panel(axes[r][0], list(range(len(values))), values, band, title, "lag k [samples]", untested=(0,))
        axes[r][0].set_ylabel(f"ρ of {output} − {output}*", fontsize=8)
        for c, (name, ccf) in enumerate(ccfs, start=1):
            values = ccf.nums("ccf", required=True)
            band = ccf.num("band", required=True)
            outside = ccf.nums("lags_outside")
            m = (len(values) - 1) // 2
            title = (f"{split}: input {name} against the {output} residual\n"
                     f"{_outside_text(outside, len(values))}")
            if split == "estimation" and ("missing_input_dynamic", name) in findings:
                title += ": a dynamic from " + name + " is missing"
            _panel(axes[r][c], list(range(-m, m + 1)), values, band, title,
                   f"lag τ [samples]: {output} residual τ samples after {name}")
            axes[r][c].set_ylabel(f"r({name}, {output} − {output}*)", fontsize=8)
        for c in range(1 + len(ccfs), columns):
            axes[r][c].set_axis_off()
    fig.suptitle(f"{common.title_of(summary)}: residual analysis (autocorrelation and input cross-correlation, "
                 f"99 % bands)", fontsize=11)
    return [common.save(fig, out_dir, "residual_analysis.png", dpi)]
