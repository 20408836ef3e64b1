"""design.png, from a directory written by `tvid design`: each generated input (the designed
multisine first) over the record, its amplitude spectrum, and every candidate's predicted
relative standard errors per parameter (log scale), the criterion's best marked."""

import math
import os

import numpy as np

from . import common
from .common import plt

COLOURS = {"designed": "tab:red", "given": "0.35", "multisine": "tab:blue", "chirp": "tab:green",
           "prbs": "tab:purple"}


def draw(directory, out_dir, dpi):
    if not common.exists(directory, "design.json"):
        return []
    info = common.read_json(os.path.join(directory, "design.json"))
    design = info.obj("design", required=True)
    column = design.text("column", required=True)
    candidates = info.objects("candidates", required=True)
    if not candidates:
        common.fail(f"{info.path}: candidates: empty")
    signals = []
    for c in candidates:
        name = c.text("name", "?")
        file = c.text("file")
        if not file:
            continue
        table = common.read_table(os.path.join(directory, file))
        signals.append((name, np.array(table.numbers(table.names[0])), np.array(table.numbers(column))))

    fig, axes = plt.subplots(3, 1, figsize=(9, 9.5), layout="constrained",
                             gridspec_kw={"height_ratios": [1.1, 1, 1.2]})
    base = design.num("base", 0.0)
    shown = 2.0  # s of the record drawn: the shapes stay readable
    peak = 0.0
    for name, t, u in signals:
        near = t <= t[0] + shown
        axes[0].plot(t[near], u[near], lw=0.7, color=COLOURS.get(name), alpha=0.85,
                     label=f"{name} (crest {np.max(np.abs(u - base)) / max(np.sqrt(np.mean((u - base) ** 2)), 1e-300):.2f})")
        f = np.fft.rfftfreq(u.size, d=(t[-1] - t[0]) / max(u.size - 1, 1))
        a = np.abs(np.fft.rfft(u - np.mean(u))) * 2 / u.size
        axes[1].plot(f[1:], a[1:], lw=0.7, color=COLOURS.get(name), alpha=0.85, label=name)
        peak = max(peak, float(np.max(a[1:])) if a.size > 1 else 0.0)
    limits = design.nums("limits", length=2)
    for y in limits or []:
        axes[0].axhline(y, color="0.3", ls=":", lw=1)
    axes[0].set_xlabel("time [s]")
    axes[0].set_ylabel(f"{design.text('input', column)}  [its unit]")
    band = design.nums("band_hz", length=2) or [0.0, 0.0]
    duration = max((t[-1] - t[0] for _, t, _ in signals), default=0.0)
    axes[0].set_title(f"{os.path.basename(info.text('experiment', '?'))}: the inputs, "
                      f"{'the first ' + format(shown, 'g') + ' s of ' + format(duration, '.3g') + ' s' if duration > shown else 'the record'} "
                      f"(band {band[0]:g} to {band[1]:g} Hz, RMS {design.num('rms', math.nan):g} about {base:g}; "
                      f"dotted: the limits)", fontsize=10)
    axes[0].legend(fontsize=8, loc="upper right", ncol=2)
    axes[1].axvspan(max(band[0], 1e-9), band[1], color="0.9", zorder=0)
    axes[1].set_xscale("log")
    axes[1].set_yscale("log")
    if peak > 0:
        axes[1].set_ylim(peak * 1e-4, peak * 3)
    axes[1].set_xlabel("frequency [Hz]")
    axes[1].set_ylabel("amplitude (DFT line)")
    axes[1].set_xlim(max(band[0], 1e-3) / 3, min(band[1] * 3, axes[1].get_xlim()[1]))
    axes[1].grid(alpha=0.3, which="both")
    axes[1].legend(fontsize=8, loc="lower left")
    axes[1].set_title("their amplitude spectra (shaded: the band)", fontsize=10)

    names = [p.text("name", "?") for p in candidates[0].objects("parameters", required=True)]
    width = 0.8 / len(candidates)
    x = np.arange(len(names))
    best = info.text("best")
    criterion = design.text("criterion", "")
    for i, c in enumerate(candidates):
        name = c.text("name", "?")
        rel = [p.num("relative_se") for p in c.objects("parameters", required=True)]
        values = [100 * v if v is not None and math.isfinite(v) else np.nan for v in rel]
        worst = c.obj("criteria").num(criterion) if criterion else None
        label = name + (f": {criterion} {100 * worst:.3g} %" if worst is not None and math.isfinite(worst) else "")
        if name == best:
            label += "  (best)"
        axes[2].bar(x + (i - (len(candidates) - 1) / 2) * width, values, width, color=COLOURS.get(name, "0.6"),
                    edgecolor="black" if name == best else "none", label=label)
    axes[2].set_xticks(x, names)
    axes[2].set_yscale("log")
    axes[2].set_ylabel("predicted relative SE [%]")
    axes[2].grid(alpha=0.3, axis="y", which="both")
    axes[2].legend(fontsize=8, loc="best")
    axes[2].set_title("predicted relative standard errors (local, at the nominal values; white noise as stated)",
                      fontsize=10)
    return [common.save(fig, out_dir, "design.png", dpi)]
