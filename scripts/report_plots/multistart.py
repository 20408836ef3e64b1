"""multistart.png: the waterfall of a multistart fit. Each start's final cost, sorted from
the lowest, with the line down from its initial cost; the reported (best) start starred; the
noise floor N·σ_n² that a fit leaving only noise would reach, with σ_n the unpredictable
part of the best fit's residual (summary.json `residuals`). Starts that end on a plateau
together found the same minimum; a plateau far above the floor is a local one. A start the
race stopped (estimation.multistart.race) is drawn as a grey square at its cost when it
stopped, with the step it stopped at."""

import math
import os

from . import common
from .common import plt
from .history import cost_label


def noise_floor(summary):
    """Σ over outputs of n·(scale·σ_n)² over the estimation samples (l2 cost), or None."""
    cost = summary.obj("cost")
    if cost.text("kind") != "l2":
        return None
    total = 0.0
    residuals = summary.obj("residuals").obj("estimation")
    for o in cost.objects("outputs"):
        r = residuals.obj(o.text("name", required=True), nullable=True)
        noise, samples = r.num("noise_rms"), r.num("samples")
        if noise is None or not samples:
            return None
        total += samples * (o.num("scale", 1.0) * noise) ** 2
    return total if math.isfinite(total) and total > 0 else None


def finite(v):
    return v is not None and math.isfinite(v)


def start_label(v):
    return f"{v:.0f}" if v is not None and math.isfinite(v) and v == int(v) else str(v)


def draw(directory, out_dir, dpi):
    if not common.exists(directory, "summary.json"):
        return []
    summary = common.read_json(os.path.join(directory, "summary.json"))
    opt = summary.obj("optimizer")
    if opt.text("name") != "multistart":
        return []
    # Each start: its number, initial and final cost, and whether it converged.
    starts = [{"start": s.num("start", required=True), "cost": s.num("cost"), "initial_cost": s.num("initial_cost"),
               "converged": s.flag("converged"), "raced_out": s.flag("raced_out"), "iterations": s.num("iterations")}
              for s in opt.objects("start_results", nullable=True)]
    if not starts:
        return []
    best = opt.num("best_start")
    ran = [s for s in starts if finite(s["cost"])]
    failed = [s for s in starts if not finite(s["cost"])]
    ran.sort(key=lambda s: (s["cost"], s["start"]))
    fig, ax = plt.subplots(figsize=(max(7.5, 0.35 * len(starts) + 5.0), 4.0), layout="constrained")
    for rank, s in enumerate(ran, start=1):
        if finite(s["initial_cost"]):
            ax.plot([rank, rank], [s["initial_cost"], s["cost"]], color="0.75", lw=1.0, zorder=1)
            ax.plot(rank, s["initial_cost"], marker="o", mfc="white", mec="0.55", ms=5, ls="none", zorder=2)
        if s["raced_out"]:
            ax.plot(rank, s["cost"], marker="s", color="0.45", ms=6, ls="none", zorder=3)
            ax.annotate(f"{start_label(s['iterations'])}", (rank, s["cost"]), textcoords="offset points", xytext=(6, -3),
                        fontsize=7, color="0.35")
        else:
            colour = "tab:blue" if s["converged"] else "tab:orange"
            ax.plot(rank, s["cost"], marker="o", color=colour, ms=6, ls="none", zorder=3)
        if s["start"] == best:
            ax.plot(rank, s["cost"], marker="*", color="tab:red", ms=16, ls="none", zorder=4)
    costs = [s["cost"] for s in ran] + [s["initial_cost"] for s in ran if finite(s["initial_cost"])]
    top = max(costs) if costs else 1.0
    for i, s in enumerate(failed, start=len(ran) + 1):  # drawn at the top: they reached no finite cost
        ax.plot(i, top, marker="x", color="black", ms=8, ls="none")
    floor = noise_floor(summary)
    if floor is not None:
        ax.axhline(floor, color="tab:green", ls="--", lw=1.2, zorder=0)
    # The legend's entries, drawn once each.
    ax.plot([], [], marker="o", mfc="white", mec="0.55", ls="-", color="0.75", label="initial cost → final")
    if any(s["converged"] for s in ran):
        ax.plot([], [], marker="o", color="tab:blue", ls="none", label="final cost, converged")
    if any(not s["converged"] and not s["raced_out"] for s in ran):
        ax.plot([], [], marker="o", color="tab:orange", ls="none", label="final cost, not converged")
    if any(s["raced_out"] for s in ran):
        ax.plot([], [], marker="s", color="0.45", ls="none", label="raced out (at the step beside it)")
    ax.plot([], [], marker="*", color="tab:red", ms=12, ls="none", label=f"best: start {start_label(best)}")
    if failed:
        ax.plot([], [], marker="x", color="black", ls="none", label="start failed")
    if floor is not None:
        ax.plot([], [], color="tab:green", ls="--", label=f"noise floor N·σ_n² ≈ {floor:.3g}")
    ax.set_yscale("log")
    order = ran + failed
    ax.set_xticks(range(1, len(order) + 1))
    ax.set_xticklabels([start_label(s["start"]) for s in order], fontsize=8)
    ax.set_xlim(0.4, len(order) + 0.6)
    ax.set_xlabel("start number, sorted by final cost (a raced-out start's: where the race stopped it)")
    ax.set_ylabel(cost_label(summary).replace("best cost", "cost"))
    ax.grid(alpha=0.3, which="major")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), framealpha=0.9)
    ax.set_title(f"{summary.text('experiment', '?')}: multistart, {len(starts)} starts of at most "
                 f"{opt.obj('lm').label('max_iterations')} LM steps", fontsize=11)
    return [common.save(fig, out_dir, "multistart.png", dpi)]
