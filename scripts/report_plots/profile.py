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
    path = os.path.join(directory, "profile.csv")
    header, rows = common.read_csv(path)
    name = info.get("parameter", header[0] if header else "?")
    v_col, d_col = common.column(header, name, path), common.column(header, "delta_chi2", path)
    points = []
    for line, row in enumerate(rows, start=2):
        try:
            points.append((common.number(row[v_col]), common.number(row[d_col])))
        except (ValueError, IndexError):
            common.fail(f"{path}:{line}: expected numbers in {name} and delta_chi2")
    optimum = info.get("optimum", {}).get("value")
    threshold = info.get("threshold", 3.841)
    fig, ax = plt.subplots(figsize=(7, 4.2), layout="constrained")
    finite = [(v, d) for v, d in points if math.isfinite(d)]
    curve = sorted(finite + ([(optimum, 0.0)] if optimum is not None else []))
    ax.plot([v for v, _ in curve], [d for _, d in curve], color="tab:blue", lw=1.5, marker="o", ms=4,
            label="profile: the others refitted")
    if optimum is not None:
        ax.plot([optimum], [0.0], marker="*", ms=12, color="tab:red", ls="none", label=f"optimum {optimum:.5g}")
    ax.axhline(threshold, color="0.3", ls=":", lw=1, label=f"95 % threshold (χ²₁ = {threshold:.2f})")
    interval = info.get("interval95", {})
    for key in ("low", "high"):
        if interval.get(key) is not None:
            ax.axvline(interval[key], color="tab:blue", lw=1, alpha=0.7)
    low, high = interval.get("low"), interval.get("high")
    text = f"profile [{'open' if low is None else f'{low:.5g}'}, {'open' if high is None else f'{high:.5g}'}]"
    linear = info.get("linearised_interval95")
    if linear:
        for x in linear:
            ax.axvline(x, color="tab:orange", ls="--", lw=1)
        ax.plot([], [], color="tab:orange", ls="--", label=f"linearised [{linear[0]:.5g}, {linear[1]:.5g}]")
    ax.plot([], [], color="tab:blue", lw=1, alpha=0.7, label=text)
    ax.set_xlabel(common.labelled(name, info.get("unit", "")))
    ax.set_ylabel("Δχ² = (S − S_min) / s²  [1]")
    low = min(0.0, min((d for _, d in finite), default=0.0))
    high = max([threshold] + [d for _, d in finite])
    ax.set_ylim(low - 0.04 * (high - low), high + 0.08 * (high - low))  # the optimum's star whole
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best", framealpha=0.9)
    title = f"{info.get('experiment', '?')}: profile likelihood of {name}"
    if info.get("better_point_found"):
        title += "\n(a grid point fitted below the optimum: profile again from it with --params)"
    elif interval.get("disconnected"):
        title += "\n(the points below the threshold form more than one valley)"
    ax.set_title(title, fontsize=10)
    return [common.save(fig, out_dir, "profile.png", dpi)]
