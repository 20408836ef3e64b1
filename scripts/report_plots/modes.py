"""modes.png, from a directory written by `tvid modes` (modes.json): each torsional mode's
shape as bars per node (the node angles of its eigenvector, the largest = 1, and the same
referred to the reference node's shaft through the gear ratios), its natural frequency and
damping ratio in the panel's title. Rigid-body modes are listed in the figure's title only."""

import math
import os

from . import common
from .common import plt


def _fmt_zeta(z):
    return "-" if z is None or not math.isfinite(z) else f"{z:.3g}"


def _mode(m):
    """The fields of a modes[] entry the figure draws, each checked."""
    return {"mode": m.label("mode"), "kind": m.text("kind", required=True),
            "frequency_hz": m.num("frequency_hz", required=True),
            "damped_frequency_hz": m.num("damped_frequency_hz", math.nan), "damping_ratio": m.num("damping_ratio"),
            "shape": m.number_map("shape", required=True),
            "shape_common_shaft": m.number_map("shape_common_shaft")}


def draw(directory, out_dir, dpi):
    path = os.path.join(directory, "modes.json")
    if not os.path.isfile(path):
        return []
    info = common.read_json(path)
    modes = [_mode(m) for m in info.objects("modes")]
    shown = [m for m in modes if m["kind"] != "rigid_body"]
    rigid = [m for m in modes if m["kind"] == "rigid_body"]
    if not modes:
        return []
    lin = info.obj("linearisation")
    nodes = lin.texts("nodes") or list(modes[0]["shape"])  # the model's order
    held = set(lin.texts("held_nodes"))
    ratios = lin.number_map("ratios")
    columns = 2 if len(shown) > 3 else 1
    rows = max(1, math.ceil(len(shown) / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(max(6.5 * columns, 8.0), 2.3 * rows + 1.2), squeeze=False,
                             layout="constrained")
    x = list(range(len(nodes)))
    width = 0.38
    geared = any(r is not None and abs(r - 1.0) > 1e-12 for r in ratios.values())

    def finite_or_0(v):
        return v if v is not None and math.isfinite(v) else 0.0

    for ax, m in zip(axes.flat, shown):
        shape = [finite_or_0(m["shape"].get(n)) for n in nodes]
        ax.bar([i - width / 2 if geared else i for i in x], shape, width if geared else 0.6, color="tab:blue",
               label="node angle")
        if geared:
            on_common_shaft = [finite_or_0(m["shape_common_shaft"].get(n)) for n in nodes]
            ax.bar([i + width / 2 for i in x], on_common_shaft, width, color="tab:orange",
                   label=f"referred to {lin.text('reference_node', 'node 0')}'s shaft")
        ax.axhline(0.0, color="0.3", lw=0.8)
        ax.set_xticks(x)
        ax.set_xticklabels([f"{n}\n(held)" if n in held else n for n in nodes], fontsize=8)
        ax.set_ylim(-1.15, 1.15)
        ax.set_ylabel("shape (Re, largest = 1)  [1]", fontsize=8)
        ax.grid(axis="y", alpha=0.3)
        kind = "" if m["kind"] == "oscillating" else f" ({m['kind']})"
        ax.set_title(f"mode {m['mode']}{kind}: f_n = {m['frequency_hz']:.4g} Hz, f_d = "
                     f"{m['damped_frequency_hz']:.4g} Hz, ζ = {_fmt_zeta(m['damping_ratio'])}", fontsize=9)
        if geared and m is shown[0]:
            ax.legend(fontsize=7, loc="best")
    for ax in list(axes.flat)[len(shown):]:
        ax.axis("off")
    op = info.obj("operating_point")
    title = (f"{info.text('experiment', '?')}: torsional modes at the start of window {op.label('window')}\n"
             f"({op.text('initial_state', '?')} start; angle-dependent elements: {op.text('angle_dependence', '?')})")
    if rigid:
        title += "\n" + ", ".join(f"mode {m['mode']} rigid body (|λ|/2π = {m['frequency_hz']:.3g} Hz)" for m in rigid)
        title += ": the line turning as one body, not drawn"
    if not shown:
        title += "\n(no twisting mode)"
    fig.suptitle(title, fontsize=10)
    return [common.save(fig, out_dir, "modes.png", dpi)]
