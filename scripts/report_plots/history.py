"""cost_history.png: the best cost against the iteration and against the simulations run,
log scale (Yoshida & Takamatsu Fig. 6); a multistart fit's starts one after the other."""

import math
import os

from . import common
from .common import plt, ticker


def cost_label(summary):
    """'best cost Σ e² [unit²]' in the unit of summary.json's cost.value."""
    cost = summary.obj("cost")
    kind = cost.text("kind", "")
    symbol = {"l2": "Σ e²", "l1": "mean |e|"}.get(kind, kind)
    units = {o.text("unit", "") for o in cost.objects("outputs")}
    if cost.text("normalize") == "spread":
        unit = "1"  # each residual divided by its output's spread
    elif len(units) == 1:
        u = units.pop()
        unit = common.squared_unit(u) if kind == "l2" else u
    else:
        unit = "mixed units"
    return common.labelled(f"best cost {symbol}".rstrip(), unit)


def read_history(directory):
    table = common.read_table(os.path.join(directory, "history.csv"))
    columns = zip(*(table.numbers(n) for n in ("iteration", "evaluations", "best_cost")))
    # The best cost is inf while no candidate has a finite cost.
    return [(k, n, e) for k, n, e in columns if math.isfinite(k) and math.isfinite(n) and math.isfinite(e) and e > 0]


def draw(directory, out_dir, dpi):
    if not (common.exists(directory, "summary.json") and common.exists(directory, "history.csv")):
        return []
    summary = common.read_json(os.path.join(directory, "summary.json"))
    points = read_history(directory)
    if not points:
        return []
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), layout="constrained")
    for ax, index, xlabel in ((axes[0], 0, "iteration [count]"), (axes[1], 1, "simulations [count]")):
        ax.plot([p[index] for p in points], [p[2] for p in points], color="tab:green", lw=1.2, marker=".", ms=3)
        ax.set_yscale("log")
        costs = [p[2] for p in points]
        if max(costs) < 100 * min(costs):  # under two decades: label 2, 3, 5 × 10^k too
            ax.yaxis.set_minor_locator(ticker.LogLocator(subs=(2.0, 3.0, 5.0)))
            plain = ticker.FuncFormatter(lambda v, _: f"{v:.3g}")
            ax.yaxis.set_major_formatter(plain)
            ax.yaxis.set_minor_formatter(plain)
        ax.xaxis.set_major_locator(ticker.MaxNLocator(integer=True))
        ax.set_xlabel(xlabel)
        ax.set_ylabel(cost_label(summary))
        ax.grid(alpha=0.3, which="both")
    fig.suptitle(f"{common.title_of(summary)}: cost history", fontsize=11)
    return [common.save(fig, out_dir, "cost_history.png", dpi)]
