"""frf.png, from a directory written by `tvid frf` (frf.csv, frf.json): the model's
frequency response (linearised at a window's start) against the measured H1 estimate:
magnitude on a log scale, phase, and the measurement's coherence."""

import os

from . import common
from .common import plt


def draw(directory, out_dir, dpi):
    csv_path, json_path = os.path.join(directory, "frf.csv"), os.path.join(directory, "frf.json")
    if not (os.path.isfile(csv_path) and os.path.isfile(json_path)):
        return []
    info = common.read_json(json_path)
    table = common.read_table(csv_path)
    if not table.rows:
        return []
    m = info.obj("measured")
    measured = m.flag("available")
    names = ["frequency_hz", "model_magnitude", "model_phase_deg"]
    if measured:
        names += ["measured_magnitude", "measured_phase_deg", "coherence"]
    col = {name: table.numbers(name) for name in names}
    freq = col["frequency_hz"]
    unit = info.text("magnitude_unit", "")
    fig, axes = plt.subplots(3 if measured else 2, 1, figsize=(8, 8.5 if measured else 6.2), sharex=True,
                             layout="constrained", gridspec_kw={"height_ratios": [3, 2, 1.3] if measured else [3, 2]})
    mag, phase = axes[0], axes[1]
    if measured:
        mag.loglog(freq, col["measured_magnitude"], color="0.55", lw=0.9, label="measured H1")
        phase.semilogx(freq, col["measured_phase_deg"], color="0.55", lw=0.9, ls="none", marker=".", ms=2)
    curve = info.obj("model_curve", nullable=True)
    mf = curve.nums("frequency_hz")
    if mf:  # the model on its finer grid: peaks resolved
        mm, mp = curve.nums("magnitude", required=True, length=len(mf)), curve.nums("phase_deg", required=True,
                                                                                  length=len(mf))
    else:
        mf, mm, mp = freq, col["model_magnitude"], col["model_phase_deg"]
    mag.loglog(mf, mm, color="tab:blue", lw=1.5, label="model (linearised)")
    phase.semilogx(mf, mp, color="tab:blue", lw=1.2)
    mag.set_ylabel(f"|H|  [{unit}]")
    mag.grid(which="both", alpha=0.3)
    mag.legend(fontsize=8, loc="best")
    phase.set_ylabel("phase  [deg]")
    phase.set_ylim(-185, 185)
    phase.set_yticks([-180, -90, 0, 90, 180])
    phase.grid(which="both", alpha=0.3)
    if measured:
        coh = axes[2]
        coh.semilogx(freq, col["coherence"], color="tab:green", lw=1.0)
        coh.set_ylim(0, 1.05)
        coh.set_ylabel("coherence γ²  [1]")
        coh.grid(which="both", alpha=0.3)
    axes[-1].set_xlabel("frequency  [Hz]")
    op = info.obj("operating_point")
    title = (f"{info.text('experiment', '?')}: FRF {info.text('input', '?')} → {info.text('output', '?')}, model at "
             f"the start of window {op.label('window')}")
    if measured:
        title += (f"\nH1 over {len(m.texts('windows'))} estimation window(s): {m.label('segments')} segments of "
                  f"{m.label('segment_length')} samples at {m.num('sample_rate_hz', 0.0):.5g} Hz")
    else:
        title += "\n(no measured H1)"
    fig.suptitle(title, fontsize=10)
    return [common.save(fig, out_dir, "frf.png", dpi)]
