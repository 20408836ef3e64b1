"""profile.png, from a directory written by `tvid profile`: Δχ² against the parameter's
value with the others refitted, the 95 % threshold (χ²₁ = 3.84), the profile interval and
the linearised one (θ̂ ± 1.96 se)."""

import math
import os

from . import common
from .common import plt


def draw(directory, out_dir, dpi):
    if not common.exists(directory, "profile.json"):
        return []
    info = common.read_json(os.path.join(directory, "profile.json"))
    table = common.read_table(os.path.join(directory, "profile.csv"))
    name = info.text("parameter", table.names[0])
    points = [(v, d) for v, d in zip(table.numbers(name), table.numbers("delta_chi2")) if math.isfinite(v)]
    optimum = info.obj("optimum").num("value")
    if optimum is not None and not math.isfinite(optimum):
        optimum = None
    threshold = info.num("threshold", 3.841)
    if not math.isfinite(threshold):
        common.fail(f"{info.path}: threshold: expected a finite number, found {threshold}")
    interval = info.obj("interval95")
    low, high = interval.num("low"), interval.num("high")
    linear = info.nums("linearised_interval95", nullable=True, length=2)
    fig, ax = plt.subplots(figsize=(7, 4.2), layout="constrained")
    finite = [(v, d) for v, d in points if math.isfinite(d)]
    curve = sorted(finite + ([(optimum, 0.0)] if optimum is not None else []))
    ax.plot([v for v, _ in curve], [d for _, d in curve], color="tab:blue", lw=1.5, marker="o", ms=4,
            label="profile: the others refitted")
    if optimum is not None:
        ax.plot([optimum], [0.0], marker="*", ms=12, color="tab:red", ls="none", label=f"optimum {optimum:.5g}")
    ax.axhline(threshold, color="0.3", ls=":", lw=1, label=f"95 % threshold (χ²₁ = {threshold:.2f})")
    for end in (low, high):
        if end is not None and math.isfinite(end):
            ax.axvline(end, color="tab:blue", lw=1, alpha=0.7)
    text = f"profile [{'open' if low is None else f'{low:.5g}'}, {'open' if high is None else f'{high:.5g}'}]"
    if linear:
        for x in linear:
            if math.isfinite(x):
                ax.axvline(x, color="tab:orange", ls="--", lw=1)
        ax.plot([], [], color="tab:orange", ls="--", label=f"linearised [{linear[0]:.5g}, {linear[1]:.5g}]")
    ax.plot([], [], color="tab:blue", lw=1, alpha=0.7, label=text)
    ax.set_xlabel(common.labelled(name, info.text("unit", "")))
    ax.set_ylabel("Δχ² = (S − S_min) / s²  [1]")
    low = min(0.0, min((d for _, d in finite), default=0.0))
    high = max([threshold] + [d for _, d in finite])
    ax.set_ylim(low - 0.04 * (high - low), high + 0.08 * (high - low))  # the optimum's star whole
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best", framealpha=0.9)
    title = f"{info.text('experiment', '?')}: profile likelihood of {name}"
    if info.flag("better_point_found"):
        title += "\n(a grid point fitted below the optimum: profile again from it with --params)"
    elif interval.flag("disconnected"):
        title += "\n(the points below the threshold form more than one valley)"
    ax.set_title(title, fontsize=10)
    return [common.save(fig, out_dir, "profile.png", dpi)]
