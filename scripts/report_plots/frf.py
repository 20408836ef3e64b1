"""frf.png, from a directory written by `tvid frf` (frf.csv, frf.json): the model's
frequency response (linearised at a window's start) against the measured H1 estimate:
magnitude on a log scale, phase, and the measurement's coherence."""

import csv
import math
import os

from . import common
from .common import plt


def _number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def draw(directory, out_dir, dpi):
    csv_path, json_path = os.path.join(directory, "frf.csv"), os.path.join(directory, "frf.json")
    if not (os.path.isfile(csv_path) and os.path.isfile(json_path)):
        return []
    info = common.read_json(json_path)
    with open(csv_path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return []
    col = {k: [_number(r.get(k)) for r in rows] for k in rows[0].keys()}
    freq = col["frequency_hz"]
    measured = info.get("measured", {}).get("available", False)
    unit = info.get("magnitude_unit", "")
    fig, axes = plt.subplots(3 if measured else 2, 1, figsize=(8, 8.5 if measured else 6.2), sharex=True,
                             layout="constrained", gridspec_kw={"height_ratios": [3, 2, 1.3] if measured else [3, 2]})
    mag, phase = axes[0], axes[1]
    if measured:
        mag.loglog(freq, col["measured_magnitude"], color="0.55", lw=0.9, label="measured H1")
        phase.semilogx(freq, col["measured_phase_deg"], color="0.55", lw=0.9, ls="none", marker=".", ms=2)
    curve = info.get("model_curve") or {}
    if curve.get("frequency_hz"):  # the model on its finer grid: peaks resolved
        mf, mm, mp = curve["frequency_hz"], curve["magnitude"], curve["phase_deg"]
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
    m = info.get("measured", {})
    op = info.get("operating_point", {})
    title = (f"{info.get('experiment', '?')}: FRF {info.get('input', '?')} → {info.get('output', '?')}, model at the "
             f"start of window {op.get('window', '?')}")
    if measured:
        title += (f"\nH1 over {len(m.get('windows', []))} estimation window(s): {m.get('segments')} segments of "
                  f"{m.get('segment_length')} samples at {m.get('sample_rate_hz', 0):.5g} Hz")
    else:
        title += "\n(no measured H1)"
    fig.suptitle(title, fontsize=10)
    return [common.save(fig, out_dir, "frf.png", dpi)]
